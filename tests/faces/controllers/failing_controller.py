"""A Webots controller with a bug: it asks for a device the e-puck has not, deep in a
function of its own, the way a misspelt name fails in a published controller."""

from controller import Robot


def setup(robot):
    return robot.getDevice("ps9x").enable(32)  # the bug: no such sensor, None


def main():
    robot = Robot()
    robot.step(32)
    setup(robot)


main()
