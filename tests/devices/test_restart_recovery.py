"""A dsPIC that restarts mid-run gets its state back at the Robot level (issue 3, item 3).

A reset stops the motors, clears the step counters and switches the LEDs off, then prints
the welcome banner. The robot notices the banner, re-applies what it had commanded and
carries on; the controller's next step still returns 0.
"""

from __future__ import annotations

from helpers import emulator_of

import ego
from tests.helpers import world_of

STEP_MS = 32


def run(robot: ego.Robot, steps: int) -> None:
    for _ in range(steps):
        assert robot.step(STEP_MS) == 0


def test_the_builtin_emulator_is_reachable_from_the_robot(builtin_sim_robot: ego.Robot) -> None:
    robot = builtin_sim_robot
    assert robot.port == ego.SIM_PORT
    assert robot.ground_truth is not None
    robot.motors.set_speed(200, 200)
    robot.encoders.enable(STEP_MS)
    run(robot, 1)
    assert world_of(robot).speeds == (200, 200)
    assert emulator_of(robot).history[-1].commands == "DEQ"
    robot.motors.set_speed(0, 0)


def test_after_a_reset_the_next_step_succeeds_and_actuators_are_reapplied(
    builtin_sim_robot: ego.Robot,
) -> None:
    robot = builtin_sim_robot
    world = world_of(robot)
    robot.encoders.enable(STEP_MS)
    robot.proximity.enable(STEP_MS)
    robot.motors.set_speed(400, -400)
    robot.leds.set("led2", 1)
    robot.leds.set("led8", 1)
    robot.leds.set("led5", 1)
    run(robot, 1)
    robot.leds.set("led5", 0)  # on, then off again: it must stay off
    run(robot, 10)
    before = robot.encoders.values
    assert world.speeds == (400, -400)

    emulator_of(robot).inject("reset")
    assert robot.step(STEP_MS) == 0

    assert robot.channel.stats.restarts == 1
    assert world.speeds == (400, -400)
    assert world.leds == (0, 0, 1, 0, 0, 0, 0, 0, 1, 0)
    after = robot.encoders.values
    # The counters continue from ego's totals: no jump back to 0.
    assert after[0] >= before[0] and after[1] <= before[1]
    assert after[0] - before[0] < 100 and before[1] - after[1] < 100
    run(robot, 5)
    later = robot.encoders.values
    assert later[0] > after[0] + 30 and later[1] < after[1] - 30
    robot.motors.set_speed(0, 0)


def test_a_reset_while_standing_still_does_not_start_the_motors(
    builtin_sim_robot: ego.Robot,
) -> None:
    robot = builtin_sim_robot
    world = world_of(robot)
    robot.motors.enable(STEP_MS)
    robot.motors.set_speed(300, 300)
    run(robot, 2)
    robot.motors.set_speed(0, 0)
    run(robot, 2)

    emulator_of(robot).inject("reset")
    assert robot.step(STEP_MS) == 0

    assert robot.channel.stats.restarts == 1
    assert world.speeds == (0, 0)
    assert robot.motors.values == (0, 0)
