"""Every invalid input to the core raises its typed error, naming the valid values (item 7)."""

from __future__ import annotations

from collections.abc import Iterator

import pytest
from helpers import IN_PROCESS_LINK

import ego
from ego.errors import (
    DeviceError,
    OutOfRangeError,
    PortNotFoundError,
    UnknownDeviceError,
)
from firmware_sim import Emulator

STEP_MS = 32


@pytest.fixture(scope="module")
def idle_robot() -> Iterator[ego.Robot]:
    """One robot for the checks that refuse before any I/O: nothing here enables anything."""
    with Emulator("webots") as emu, ego.Robot(emu.path, link_settings=IN_PROCESS_LINK) as robot:
        yield robot
        assert robot.channel.stats.batches == 0, "a refused call reached the wire"


def test_an_unknown_device_name_lists_the_valid_names(idle_robot: ego.Robot) -> None:
    with pytest.raises(UnknownDeviceError) as info:
        idle_robot.device("ps42")
    message = str(info.value)
    assert "'ps42'" in message
    for name in ("ps0", "ps7", "gs2", "ls7", "led9", "left wheel motor", "accelerometer", "mic2"):
        assert name in message
    assert isinstance(info.value, KeyError)  # except KeyError keeps working


def test_device_finds_the_family_of_a_webots_name(idle_robot: ego.Robot) -> None:
    assert idle_robot.device("ps3") is idle_robot.proximity
    assert idle_robot.device("right wheel sensor") is idle_robot.encoders
    assert idle_robot.device("led8") is idle_robot.leds


@pytest.mark.parametrize("speeds", [(1200, 0), (0, -1001), (1000.6, 0)])
def test_a_speed_above_the_limit_is_refused(
    sim_robot: ego.Robot, emulator: Emulator, speeds: tuple[float, float]
) -> None:
    sim_robot.motors.set_speed(100, 100)
    with pytest.raises(OutOfRangeError) as info:
        sim_robot.motors.set_speed(*speeds)
    message = str(info.value)
    assert str(max(speeds, key=abs)) in message
    assert "-1000..1000" in message
    assert "refused" in message
    assert isinstance(info.value, ValueError)
    # Refused, not clamped: the previous command stands and goes out unchanged.
    assert sim_robot.motors.speed == (100, 100)
    sim_robot.step(STEP_MS)
    assert emulator.world.speeds == (100, 100)
    sim_robot.motors.set_speed(0, 0)


@pytest.mark.parametrize("bad", ["fast", None, [100], True])
def test_a_speed_that_is_not_a_number_is_a_type_error(idle_robot: ego.Robot, bad: object) -> None:
    with pytest.raises(TypeError, match="must be a number"):
        idle_robot.motors.set_speed(bad, 0)  # type: ignore[arg-type]


@pytest.mark.parametrize("bad", [float("nan"), float("inf"), float("-inf")])
def test_a_speed_that_is_not_finite_is_refused(idle_robot: ego.Robot, bad: float) -> None:
    with pytest.raises(OutOfRangeError, match=r"-1000\.\.1000"):
        idle_robot.motors.set_speed(0, bad)


def test_an_led_value_outside_0_to_2_is_refused(idle_robot: ego.Robot) -> None:
    with pytest.raises(OutOfRangeError, match=r"value for led1 3 is outside 0\.\.2"):
        idle_robot.leds.set("led1", 3)
    with pytest.raises(OutOfRangeError, match=r"0\.\.2"):
        idle_robot.leds.set(1, -1)


@pytest.mark.parametrize("led", [10, -1, 99])
def test_an_led_number_out_of_range_is_refused(idle_robot: ego.Robot, led: int) -> None:
    with pytest.raises(OutOfRangeError, match=r"LED number .* is outside 0\.\.9"):
        idle_robot.leds.set(led, 1)


def test_an_unknown_led_name_lists_the_leds(idle_robot: ego.Robot) -> None:
    with pytest.raises(UnknownDeviceError, match=r"led0, led1, .*led9"):
        idle_robot.leds.set("led10", 1)


@pytest.mark.parametrize("period", [0, -32, 32.5])
def test_a_sampling_period_that_is_not_a_positive_whole_number_is_refused(
    idle_robot: ego.Robot, period: float
) -> None:
    with pytest.raises(OutOfRangeError, match=r"sampling period .*1\.\.86400000 ms"):
        idle_robot.proximity.enable(period)  # type: ignore[arg-type]
    with pytest.raises(OutOfRangeError, match=r"1\.\.86400000 ms"):
        idle_robot.microphones.enable_buffer(period)  # type: ignore[arg-type]
    assert not idle_robot.proximity.enabled


def test_a_sampling_period_that_is_not_a_number_is_a_type_error(idle_robot: ego.Robot) -> None:
    with pytest.raises(TypeError, match="sampling period must be a number"):
        idle_robot.light.enable("64")  # type: ignore[arg-type]


def test_an_unknown_accelerometer_mode_names_the_modes(idle_robot: ego.Robot) -> None:
    with pytest.raises(OutOfRangeError, match="'raw', 'spherical'"):
        idle_robot.accelerometer.enable(STEP_MS, mode="polar")
    assert not idle_robot.accelerometer.enabled
    assert idle_robot.accelerometer.mode.value == "raw"


@pytest.mark.parametrize("ms", [0, -1, 2.5])
def test_a_time_step_that_is_not_a_positive_whole_number_is_refused(
    idle_robot: ego.Robot, ms: float
) -> None:
    with pytest.raises(OutOfRangeError, match=r"time step .*1\.\.86400000 ms"):
        idle_robot.step(ms)  # type: ignore[arg-type]
    assert idle_robot.time_s == 0.0


def test_reading_a_sensor_that_is_not_enabled_raises(idle_robot: ego.Robot) -> None:
    with pytest.raises(DeviceError, match="proximity sensors not enabled"):
        _ = idle_robot.proximity.values
    with pytest.raises(DeviceError, match="not enabled"):
        idle_robot.light.value("ls0")
    with pytest.raises(DeviceError, match="not enabled"):
        _ = idle_robot.encoders.values
    with pytest.raises(DeviceError, match="not enabled"):
        _ = idle_robot.accelerometer.acceleration_mps2
    with pytest.raises(DeviceError, match="enable_buffer"):
        _ = idle_robot.microphones.buffer


def test_reading_a_sensor_before_its_first_step_raises(sim_robot: ego.Robot) -> None:
    sim_robot.floor.enable(STEP_MS)
    with pytest.raises(DeviceError, match="not sampled yet"):
        _ = sim_robot.floor.values
    sim_robot.step(STEP_MS)
    assert len(sim_robot.floor.values) == 3


def test_reading_spherical_values_in_raw_mode_says_how_to_enable_them(
    sim_robot: ego.Robot,
) -> None:
    sim_robot.accelerometer.enable(STEP_MS)
    sim_robot.step(STEP_MS)
    with pytest.raises(DeviceError, match="mode='spherical'"):
        _ = sim_robot.accelerometer.spherical


def test_a_port_that_does_not_exist_is_named_in_the_error() -> None:
    missing = "/dev/ttyEGO-does-not-exist"
    with pytest.raises(PortNotFoundError, match=missing) as info:
        ego.Robot(missing)
    assert isinstance(info.value, FileNotFoundError)
