"""The plausibility guard: what a reply of the right length cannot tell, checked where it can be.

The e-puck link has no checksum. A flipped bit in a reply is caught when it takes a value
out of its range; a command the dsPIC misread (a flipped bit on the way in) is caught when
it changed something ego reads back: the speeds (E after every D) and the step counters.
"""

from __future__ import annotations

import logging
import struct
import time

import pytest
from fakes import INSTANT_LINK, ScriptedTransport

import ego
from ego.devices.base import Verdict
from ego.devices.encoders import Encoders, wrap_int16
from ego.seam.batch import Request
from ego.seam.profile import Command, Firmware
from ego.serial.link import Link
from ego.serial.profiles import PROFILES
from firmware_sim import Emulator, World

STEP_MS = 16
GET_STEPS = Request(Command.GET_STEPS)


def fresh_encoders(left: int, right: int, now: float) -> Encoders:
    encoders = Encoders(PROFILES[Firmware.WEBOTS])
    encoders.counters.apply(GET_STEPS, (left, right), 0, now)
    return encoders


def judged(encoders: Encoders, values: tuple[int, int], now: float) -> Verdict:
    """What the step transaction does with one reply: validate, and tell a refusal."""
    verdict = encoders.counters.validate(GET_STEPS, values, now)
    if not verdict.fine:
        encoders.counters.refused(verdict, now)
    return verdict


def planned(encoders: Encoders) -> list[Request]:
    return [r for part in encoders.parts for r in part.plan(0)]


def test_a_counter_jump_seen_once_is_refused_and_the_next_true_reading_taken() -> None:
    now = time.monotonic()
    encoders = fresh_encoders(100, 100, now)
    assert "jumped" in (judged(encoders, (100, 30000), now).problem or "")
    assert judged(encoders, (101, 102), now).fine
    assert [r for r in planned(encoders) if r.command is Command.SET_STEPS] == []
    # a garbled reply changes nothing on the dsPIC


def test_a_counter_jump_seen_twice_sets_the_dspic_counters_back() -> None:
    now = time.monotonic()
    encoders = fresh_encoders(100, -200, now)
    assert "overwritten" not in (judged(encoders, (100, 30000), now).problem or "")
    why = judged(encoders, (100, 30001), now).problem
    assert why is not None and "overwritten" in why
    assert planned(encoders) == [Request(Command.SET_STEPS, (100, -200))]


def test_two_different_jumps_are_two_garbles_not_an_overwrite() -> None:
    now = time.monotonic()
    encoders = fresh_encoders(0, 0, now)
    assert not judged(encoders, (9000, 0), now).fine
    why = judged(encoders, (0, -9000), now).problem
    assert why is not None and "overwritten" not in why
    assert planned(encoders) == []


def test_validating_changes_nothing() -> None:
    """A verdict has no side effects: asked twice, the same answer, and the same plan."""
    now = time.monotonic()
    encoders = fresh_encoders(100, -200, now)
    encoders.counters.refused(encoders.counters.validate(GET_STEPS, (100, 30000), now), now)
    first = encoders.counters.validate(GET_STEPS, (100, 30001), now)
    second = encoders.counters.validate(GET_STEPS, (100, 30001), now)
    assert first == second and first.correction == Request(Command.SET_STEPS, (100, -200))
    assert planned(encoders) == []  # only refused() acts on it


def test_counters_overwritten_on_the_dspic_are_set_back_within_the_step(
    sim_robot: ego.Robot,
    emulator: Emulator,
    world: World,
    caplog: pytest.LogCaptureFixture,
) -> None:
    """What a command byte misread as P does: the robot's totals must not jump with it."""
    sim_robot.encoders.enable(STEP_MS)
    for _ in range(3):
        assert sim_robot.step(STEP_MS) == 0
    before = sim_robot.encoders.values
    world.set_steps(20000, -20000)  # the wheels stand still: only the counters changed
    caplog.set_level(logging.WARNING, logger="ego")
    assert sim_robot.step(STEP_MS) == 0
    assert sim_robot.encoders.values == before
    assert world.steps_int16() == tuple(wrap_int16(v) for v in before)
    assert any("overwritten" in r.getMessage() for r in caplog.records)


def test_a_misread_d_is_caught_by_the_e_behind_it_and_sent_again() -> None:
    """Speeds not sampled: the E that travels with every D still checks them."""
    misread = struct.pack("<2h", 300, 44)
    held = struct.pack("<2h", 300, 300)
    stopped = struct.pack("<2h", 0, 0)
    fake = ScriptedTransport([misread, held, stopped])
    robot = ego.Robot(channel=Link(fake, "webots", INSTANT_LINK))
    try:
        robot.motors.set_speed(300, 300)
        assert robot.step(STEP_MS) == 0
        d_then_e = bytes([Command.SET_SPEED]) + struct.pack("<2h", 300, 300)
        d_then_e += bytes([Command.GET_SPEED, 0])
        assert fake.writes == [d_then_e, d_then_e]
        assert robot.motors.values == (300, 300)
    finally:
        robot.close()
    assert fake.writes[-1].startswith(bytes([Command.SET_SPEED]) + struct.pack("<2h", 0, 0))
