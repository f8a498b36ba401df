"""A dsPIC that restarts mid-run gets its state back at the Robot level (issue 3, item 3).

A reset stops the motors, clears the step counters and switches the LEDs off, then prints
the welcome banner. The robot notices the banner, re-applies what it had commanded and
carries on; the controller's next step still returns 0.
"""

from __future__ import annotations

import pytest
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


def test_a_reset_whose_banner_comes_in_two_pieces_is_not_taken_for_the_firmware_answer() -> None:
    """Issue 35: on a loaded machine the banner's lines came apart; the link, draining
    until the line was quiet, stopped between them and took what came next for the
    answer to its V ("reply 'on robot type "H" for help' to 'V' does not start with 'v'",
    or no answer at all). It drains until the banner's last line is in."""
    from helpers import IN_PROCESS_LINK

    from ego.errors import RobotResetError
    from ego.seam.batch import Request
    from ego.seam.profile import Command
    from ego.serial.link import Link
    from ego.serial.protocol import encode_batch
    from ego.serial.transport import SerialTransport
    from firmware_sim import Emulator, FaultTimings

    with Emulator("webots", seed=1, timings=FaultTimings(banner_gap_s=0.15)) as emu:
        link = Link(SerialTransport(emu.path), settings=IN_PROCESS_LINK)  # a 20 ms quiet line
        try:
            batch = encode_batch([Request(Command.PROXIMITY)], link.profile)
            link.exchange(batch)
            emu.inject("reset", batch=emu.batches + 1)
            # The silent batch restarts the dsPIC; the V behind it meets the banner's first
            # line, and is asked again: its answer must be the firmware's, not line two.
            link.exchange(encode_batch([Request(Command.SET_SPEED, (100, 100))], link.profile))
            replies = link.ascii_command("V")
            assert replies and replies[0].startswith("v"), replies
            with pytest.raises(RobotResetError):
                link.exchange(batch)
            assert link.exchange(batch) == emu.history[-1].reply  # and the next step works
        finally:
            link.close()
