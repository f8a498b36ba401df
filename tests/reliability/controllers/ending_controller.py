"""Controllers that end the ways real ones do, without stopping the robot themselves.

Usage: ego run --port PORT ending_controller.py STYLE
       python ending_controller.py STYLE          (the port from EGO_PORT)

Every style sets the wheels turning and some LEDs on, prints "running" once it has
stepped, and then, depending on STYLE:
- webots-ends: a Webots-face controller at module level steps 10 times and ends;
- webots-main: the same, with its Robot inside main();
- plain-function: an ``ego.Robot`` local to a function, never closed, steps 10 times;
- plain-raises: the same robot, and then an exception escapes;
- webots-forever, plain-forever: step until the process is ended from outside.
None of them calls close(), cleanup() or leaves a ``with`` block: what stops the robot
is ego.
"""

import sys

TIME_STEP = 32


def webots_robot():
    from controller import Robot

    robot = Robot()
    for side, velocity in (("left", 2.0), ("right", -2.0)):
        motor = robot.getDevice(f"{side} wheel motor")
        motor.setPosition(float("inf"))
        motor.setVelocity(velocity)
    robot.getDevice("led1").set(1)
    robot.getDevice("led8").set(1)
    return lambda: robot.step(TIME_STEP)


def plain_robot():
    import ego

    # A library Robot leaves signals alone unless asked (ego run asks for its controller).
    robot = ego.Robot(handle_signals=True)
    robot.motors.set_speed(300, -300)
    robot.leds.set(1, 1)
    robot.leds.set(8, 1)
    return lambda: robot.step(TIME_STEP)


def drive(step, forever=False):
    step()
    print("running", flush=True)
    for _ in range(9):
        step()
    while forever and step() != -1:
        pass


def main():
    drive(webots_robot())


def plain_function(forever=False, then_raise=False):
    step = plain_robot()
    drive(step, forever)
    if then_raise:  # the robot is still referenced by this frame as the error escapes
        raise RuntimeError("a bug in the controller")


style = sys.argv[1]
if style == "webots-ends":
    drive(webots_robot())
elif style == "webots-main":
    main()
elif style == "webots-forever":
    drive(webots_robot(), forever=True)
elif style == "plain-function":
    plain_function()
elif style == "plain-forever":
    plain_function(forever=True)
elif style == "plain-raises":
    plain_function(then_raise=True)
else:
    sys.exit(f"unknown style {style!r}")
