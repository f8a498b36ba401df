"""One batch per step, as the thesis schedules it (issue 3, item 2).

A sensor's command is queued only when its sampling period is due, an actuator's only when
its value changed, and everything due in one step travels in one batch. The emulator's
``history`` records the letters of every batch it answered (actuator-only ones included).
"""

from __future__ import annotations

import logging

import pytest
from helpers import IN_PROCESS_LINK

import ego
from firmware_sim import Emulator

STEP_MS = 32


def letters_per_step(
    robot: ego.Robot, emulator: Emulator, steps: int, ms: int = STEP_MS
) -> list[str]:
    """The command letters each step sent ("" for a step that sent nothing)."""
    sent: list[str] = []
    for _ in range(steps):
        before = robot.channel.stats.batches
        assert robot.step(ms) == 0
        batches = robot.channel.stats.batches - before
        assert batches in (0, 1), f"a step sent {batches} batches"
        sent.append(emulator.history[-1].commands if batches else "")
    return sent


def test_sensor_commands_are_queued_only_when_their_period_is_due(
    sim_robot: ego.Robot, emulator: Emulator
) -> None:
    sim_robot.proximity.enable(64)
    sim_robot.light.enable(128)
    sent = letters_per_step(sim_robot, emulator, 8)
    # 32 ms steps: N every 2nd step, O every 4th, nothing at all in between.
    assert sent == ["NO", "", "N", "", "NO", "", "N", ""]


def test_the_family_is_fetched_at_its_members_shortest_period(
    sim_robot: ego.Robot, emulator: Emulator
) -> None:
    sim_robot.proximity.enable(128, ["ps0", "ps1"])
    sim_robot.proximity.enable(64, ["ps7"])
    assert sim_robot.proximity.sampling_period("ps0") == 128
    assert sim_robot.proximity.sampling_period() == 64
    assert letters_per_step(sim_robot, emulator, 4) == ["N", "", "N", ""]


def test_a_disabled_sensor_is_no_longer_fetched(sim_robot: ego.Robot, emulator: Emulator) -> None:
    sim_robot.proximity.enable(STEP_MS)
    sim_robot.accelerometer.enable(STEP_MS)
    assert letters_per_step(sim_robot, emulator, 1) == ["aN"]
    sim_robot.proximity.disable()
    assert letters_per_step(sim_robot, emulator, 2) == ["a", "a"]
    assert sim_robot.proximity.sampling_period() is None


def test_the_same_speed_twice_sends_one_d_confirmed_by_e(
    sim_robot: ego.Robot, emulator: Emulator
) -> None:
    sim_robot.motors.set_speed(300, 300)
    first = letters_per_step(sim_robot, emulator, 1)
    sim_robot.motors.set_speed(300, 300)
    again = letters_per_step(sim_robot, emulator, 2)
    sim_robot.motors.set_speed(300, -300)
    changed = letters_per_step(sim_robot, emulator, 1)
    sim_robot.motors.set_speed(0, 0)

    assert first == ["DE"]
    assert again == ["", ""]
    assert changed == ["DE"]


def test_the_same_led_value_twice_sends_one_l(sim_robot: ego.Robot, emulator: Emulator) -> None:
    sim_robot.leds.set("led1", 1)
    first = letters_per_step(sim_robot, emulator, 1)
    sim_robot.leds.set("led1", 1)
    sim_robot.leds.set(1, ego.LedValue.ON)
    again = letters_per_step(sim_robot, emulator, 1)
    sim_robot.leds.set("led1", 0)

    assert first == ["L"]
    assert again == [""]


def test_everything_due_in_one_step_goes_in_one_batch(
    sim_robot: ego.Robot, emulator: Emulator
) -> None:
    robot = sim_robot
    for family in (robot.accelerometer, robot.proximity, robot.floor, robot.light):
        family.enable(STEP_MS)
    robot.encoders.enable(STEP_MS)
    robot.motors.enable(STEP_MS)
    robot.microphones.enable(STEP_MS)
    robot.microphones.enable_buffer(STEP_MS)
    robot.motors.set_speed(100, -100)
    robot.leds.set("led2", 1)
    robot.leds.set("led5", 1)
    robot.encoders.set(10, 20)
    batches_before = robot.channel.stats.batches
    records_before = len(emulator.history)

    assert robot.step(STEP_MS) == 0

    assert robot.channel.stats.batches == batches_before + 1
    assert len(emulator.history) == records_before + 1
    # Setters first, so that P precedes Q (encoders.set is read back in the same step) and
    # the E confirming the speeds comes after every command that could be misread as D.
    assert emulator.history[-1].commands == "DLLPEQaNMOuU"
    assert robot.encoders.values == pytest.approx((10, 20), abs=2)  # the wheels turn
    robot.motors.set_speed(0, 0)


def test_a_step_with_nothing_due_sends_no_bytes(sim_robot: ego.Robot) -> None:
    sim_robot.proximity.enable(1000)
    assert sim_robot.step(STEP_MS) == 0
    sent = sim_robot.channel.stats.bytes_sent
    for _ in range(5):
        assert sim_robot.step(STEP_MS) == 0
    assert sim_robot.channel.stats.bytes_sent == sent


def test_step_returns_zero_and_minus_one_once_closed(emulator: Emulator) -> None:
    robot = ego.Robot(emulator.path, link_settings=IN_PROCESS_LINK)
    robot.proximity.enable(STEP_MS)
    assert robot.step(STEP_MS) == 0
    robot.close()
    assert robot.step(STEP_MS) == -1
    assert robot.step(STEP_MS) == -1
    robot.close()  # idempotent


def test_time_s_is_the_sum_of_the_steps(sim_robot: ego.Robot) -> None:
    assert sim_robot.time_s == 0.0
    for ms in (32, 32, 10, 1, 64):
        sim_robot.step(ms)
    assert sim_robot.time_s == pytest.approx(0.139)
    assert sim_robot.steps == 5


def test_an_overrun_is_counted_when_the_step_is_shorter_than_its_io(
    sim_robot: ego.Robot, caplog: pytest.LogCaptureFixture
) -> None:
    robot = sim_robot
    for family in (robot.accelerometer, robot.proximity, robot.floor, robot.light):
        family.enable(1)
    robot.encoders.enable(1)
    robot.motors.enable(1)
    robot.microphones.enable(1)
    caplog.set_level(logging.WARNING, logger="ego.core.scheduler")
    steps = 10
    # Each batch is 10 command bytes and 62 reply bytes: over 3 ms of line time at
    # 230400 baud, however fast the host, so every 1 ms step overruns.
    for _ in range(steps):
        assert robot.step(1) == 0

    assert robot.overruns == steps
    assert robot.clock.worst_overrun_s > 0
    assert any("overran" in r.getMessage() for r in caplog.records)
    assert robot.time_s == pytest.approx(steps / 1000)  # controller time does not stretch
