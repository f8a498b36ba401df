"""Each step is a transaction over the device parts: plan, validate (no side effects),
refused or apply, reset; the batch order is each command's declared phase."""

from __future__ import annotations

import time

import pytest
from helpers import emulator_of

import ego
from ego.core.transaction import run_step
from ego.devices.base import PHASE, Device, Phase, Sensor
from ego.devices.motors import SpeedReadback, WheelSpeeds
from ego.seam.batch import Request
from ego.seam.profile import Command, Firmware
from ego.serial.profiles import PROFILES

WEBOTS = PROFILES[Firmware.WEBOTS]


def test_setters_are_declared_first_and_everything_else_reads() -> None:
    setters = {c for c, phase in PHASE.items() if phase is Phase.SET}
    assert setters == {Command.SET_SPEED, Command.SET_LED, Command.SET_STEPS}


def test_no_part_is_both_an_actuator_and_a_sensor(sim_robot: ego.Robot) -> None:
    for family in sim_robot.families:
        for part in family.parts:
            plans_setters = type(part).plan is not Device.plan and not isinstance(part, Sensor)
            assert not (isinstance(part, Sensor) and plans_setters)
    assert [type(p) for p in sim_robot.motors.parts] == [WheelSpeeds, SpeedReadback]


def _state(robot: ego.Robot) -> str:
    """Every part's attributes, as text (what validate must leave as it was)."""
    return repr([sorted(vars(p).items(), key=str) for f in robot.families for p in f.parts])


def test_validating_a_reply_changes_no_part(builtin_sim_robot: ego.Robot) -> None:
    robot = builtin_sim_robot
    robot.motors.set_speed(100, 100)
    robot.encoders.enable(16)
    robot.proximity.enable(16)
    robot.step(16)
    before = _state(robot)
    now = time.monotonic()
    cases = [
        (robot.motors.wheels, Request(Command.GET_SPEED), (5, 5)),
        (robot.encoders.counters, Request(Command.GET_STEPS), (30000, -30000)),
        (robot.proximity, Request(Command.PROXIMITY), (9999,) * 8),
    ]
    for part, request, values in cases:
        first = part.validate(request, values, now + 0.001)
        assert not first.fine
        assert part.validate(request, values, now + 0.001) == first
    assert _state(robot) == before


def test_a_refused_speed_echo_sends_the_speeds_again_in_the_next_attempt() -> None:
    wheels = WheelSpeeds(WEBOTS)
    wheels.set(300, 300)
    wheels.apply(Request(Command.SET_SPEED, (300, 300)), (), 0, 0.0)
    assert wheels.plan(0) == []
    verdict = wheels.validate(Request(Command.GET_SPEED), (300, 44), 0.0)
    assert wheels.plan(0) == []  # the verdict alone did nothing
    wheels.refused(verdict, 0.0)
    assert wheels.plan(0) == [Request(Command.SET_SPEED, (300, 300)), Request(Command.GET_SPEED)]


def test_one_batch_a_step_with_setters_before_reads(builtin_sim_robot: ego.Robot) -> None:
    robot = builtin_sim_robot
    robot.proximity.enable(16)
    robot.encoders.enable(16)
    robot.step(16)
    robot.encoders.set(10, 20)
    robot.leds.set(1, 1)
    robot.motors.set_speed(50, 50)
    before = len(emulator_of(robot).history)
    robot.step(16)
    (record,) = list(emulator_of(robot).history)[before:]
    letters = record.commands
    assert letters.index("Q") > letters.index("P")
    reads = [letters.index(c) for c in "NQE" if c in letters]
    assert max(letters.index(c) for c in "DLP") < min(reads), letters
    assert robot.encoders.values == (10, 20)


def test_the_camera_is_captured_on_the_step_clock(builtin_sim_robot: ego.Robot) -> None:
    camera = builtin_sim_robot.camera
    camera.set_size(64, 48)
    camera.enable(64)
    for _ in range(8):  # 8 steps of 16 ms: a frame at 0 and at 64 ms
        builtin_sim_robot.step(16)
    assert camera.frame_count == 2


def test_a_step_gives_up_after_three_implausible_replies() -> None:
    class Stubborn(Sensor):
        family = "stubborn"
        names = ("s",)
        command = Command.PROXIMITY

        def validate(self, request, values, now_s):  # type: ignore[no-untyped-def]
            from ego.devices.base import Verdict

            return Verdict("never plausible")

        def take(self, values):  # type: ignore[no-untyped-def]
            raise AssertionError("an implausible reply must never be applied")

    part = Stubborn(WEBOTS)
    part.enable(16)

    class Channel:
        profile = WEBOTS

        def __init__(self) -> None:
            from ego.serial.link import LinkStats

            self.stats = LinkStats()
            self.batches = 0

        def exchange(self, batch):  # type: ignore[no-untyped-def]
            self.batches += 1
            return bytes(batch.reply_size)

    channel = Channel()
    with pytest.raises(ego.errors.ProtocolError, match="never plausible"):
        run_step([part], channel, 0, lambda: None)  # type: ignore[arg-type]
    assert channel.batches == 3 and channel.stats.faults["implausible"] == 3
