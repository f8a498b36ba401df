"""ego reads each quirk of the real firmwares right (docs/protocol.md, "Quirks").

Each test plays the bytes the real firmware sends, from a scripted transport, and quotes
the source line it follows: GCtronic's `program/DemoGCtronic-complete/Asercom.c` and its
library (`e_acc.c`, `e_micro.c`, `e_motors.c`), and Webots' `transfer/firmware/firmware.c`.
The emulator models the same quirks independently (tests/unit/test_dspic_fidelity.py).
"""

from __future__ import annotations

import math
import struct
from collections.abc import Iterator

import numpy as np
import pytest
from fakes import INSTANT_LINK, ScriptedTransport

import ego
from ego.core.ports import default_baud
from ego.devices.accelerometer import ANGLE_OVERSHOOT
from ego.devices.motors import real_speed_steps
from ego.errors import UnsupportedDeviceError
from ego.seam.profile import Command, Firmware
from ego.serial.link import Link

STEP_MS = 16


@pytest.fixture
def robot_on() -> Iterator[object]:
    robots: list[ego.Robot] = []

    def make(script: list[bytes], firmware: str = "webots") -> tuple[ego.Robot, ScriptedTransport]:
        fake = ScriptedTransport(script)
        robot = ego.Robot(channel=Link(fake, firmware, INSTANT_LINK))
        robots.append(robot)
        return robot, fake

    yield make
    for robot in robots:
        script = robot.channel.transport.script  # type: ignore[attr-defined]
        script.clear()
        script.append(bytes(4))  # the E that confirms the stop at close
        robot.close()


# -- a / A -------------------------------------------------------------------------------------


def test_an_all_zero_accelerometer_is_no_data_not_an_acceleration(robot_on) -> None:  # type: ignore[no-untyped-def]
    """Asercom.c, 'a': in Overo mode `if(isEpuckVersion1_3()) accx = accy = accz = 0`. ego
    used to turn that into (24.5, -24.5, -24.5) m/s^2."""
    robot, _ = robot_on([bytes(6)], "gctronic")
    robot.accelerometer.enable(STEP_MS)
    with pytest.raises(UnsupportedDeviceError, match="no accelerometer data on this robot"):
        robot.step(STEP_MS)
    assert not robot.accelerometer.enabled  # asked no more
    with pytest.raises(ego.errors.DeviceError):
        robot.accelerometer.acceleration_mps2  # noqa: B018  # never a value


def test_spherical_angles_may_overshoot_as_the_firmware_computes_them(robot_on) -> None:  # type: ignore[no-untyped-def]
    """e_acc.c: inclination = 90 - atan2f(z, r) * CST_RADIAN, orientation = atan2f(x, y) *
    CST_RADIAN + 180, CST_RADIAN = 180/3.1415: -0.0026 and 360.0053 happen; the magnitude
    is in counts (sqrtf of the squared counts less their offsets)."""
    k = 180 / 3.1415
    inclination = 90 - (math.pi / 2) * k
    orientation = math.pi * k + 180
    assert inclination < 0 and orientation > 360
    robot, _ = robot_on([struct.pack("<3f", 801.5, orientation, inclination)])
    robot.accelerometer.enable(STEP_MS, mode="spherical")
    assert robot.step(STEP_MS) == 0
    magnitude, got_orientation, got_inclination = robot.accelerometer.spherical
    assert magnitude == pytest.approx(801.5)
    assert got_orientation == pytest.approx(orientation, abs=1e-3)
    assert got_inclination == pytest.approx(inclination, abs=1e-3)
    assert ANGLE_OVERSHOOT < 0.011


def test_spherical_angles_far_out_of_range_are_still_corruption(robot_on) -> None:  # type: ignore[no-untyped-def]
    bad = struct.pack("<3f", 800.0, 361.0, 45.0)
    good = struct.pack("<3f", 800.0, 90.0, 45.0)
    robot, _ = robot_on([bad, good])
    robot.accelerometer.enable(STEP_MS, mode="spherical")
    assert robot.step(STEP_MS) == 0
    assert robot.accelerometer.spherical.orientation_deg == 90.0
    assert robot.channel.stats.faults["implausible"] == 1


# -- M -----------------------------------------------------------------------------------------


def test_floor_sensors_without_the_ground_module_are_named_missing(robot_on) -> None:  # type: ignore[no-untyped-def]
    """firmware.c, 'M': e_i2cp_read(0xC0, ...) bytes with no ACK check: 0xFF each."""
    robot, _ = robot_on([b"\xff" * 6])
    robot.floor.enable(STEP_MS)
    with pytest.raises(UnsupportedDeviceError, match="ground module is not fitted"):
        robot.step(STEP_MS)
    assert not robot.floor.enabled


def test_stock_bluetooth_floor_reply_carries_two_cliff_values(robot_on) -> None:  # type: ignore[no-untyped-def]
    """Asercom.c, 'M' with CLIFF_SENSORS: 6 ground bytes then 4 cliff bytes."""
    from ego.serial.firmware import gctronic_profile

    robot, _ = robot_on([struct.pack("<5H", 500, 600, 700, 11, 12)], "gctronic")
    profile = gctronic_profile(3, False)
    robot.channel._info = type(robot.channel.info)(profile)  # as probed in selector 3
    robot.floor.set_profile(profile)
    robot.floor.enable(STEP_MS)
    assert robot.step(STEP_MS) == 0
    assert robot.floor.values == (500, 600, 700)


# -- U -----------------------------------------------------------------------------------------


def test_microphone_index_is_the_oldest_sample_and_samples_are_unsigned(robot_on) -> None:  # type: ignore[no-untyped-def]
    """Asercom.c, 'U': `n = e_last_mic_scan_id` after 600 bytes of e_mic_scan[3][100]; the
    ADC interrupt writes slot e_last_mic_scan_id next, so it holds the oldest sample."""
    samples = np.arange(300, dtype=np.uint16).reshape(3, 100) + 2000  # slot i holds 2000 + i
    index = 37
    robot, _ = robot_on([samples.astype("<u2").tobytes() + bytes([index])])
    robot.microphones.enable_buffer(STEP_MS)
    assert robot.step(STEP_MS) == 0
    buffer = robot.microphones.buffer
    assert buffer.dtype == np.uint16
    assert buffer[0, 0] == 2000 + index  # the oldest first
    assert buffer[0, -1] == 2000 + index - 1  # the newest last
    assert buffer[2, 0] == 2200 + index


# -- S -----------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("firmware", "resent"), [("gctronic", True), ("webots", False)]
)  # fmt: skip
def test_ascii_stop_is_followed_as_each_firmware_does_it(
    robot_on,
    firmware: str,
    resent: bool,  # type: ignore[no-untyped-def]
) -> None:
    """Asercom.c, 'S': speeds to 0 and e_set_led(8, 0) (the ring), but speedl/speedr, which E
    echoes, are kept; firmware.c behaves alike on the wheels but its S clears the echo too
    (docs/protocol.md, quirk "S"). Either way ego must not drive off again afterwards."""
    held = struct.pack("<2h", 300, 300)
    robot, fake = robot_on([held, b"s\r\n", bytes(4)], firmware)
    robot.motors.set_speed(300, 300)
    robot.leds.set(1, 1)
    assert robot.step(STEP_MS) == 0
    assert robot.ascii_command("S") == ["s"]
    assert robot.motors.speed == (0, 0)
    assert robot.leds.get(1) == 0
    assert robot.step(STEP_MS) == 0
    d_zero = bytes([Command.SET_SPEED]) + struct.pack("<2h", 0, 0)
    assert fake.writes[-1].startswith(d_zero) is resent
    assert not any(w.startswith(bytes([Command.SET_SPEED]) + held) for w in fake.writes[2:])


# -- K -----------------------------------------------------------------------------------------


def test_calibration_waits_for_its_last_line_and_sends_nothing_meanwhile(robot_on) -> None:  # type: ignore[no-untyped-def]
    """Asercom.c, 'K': "k, Starting calibration - Remove any object in sensors range", the
    calibration, then "k, Calibration finished"."""
    robot, fake = robot_on(
        [b"k, Starting calibration - Remove any object in sensors range\r\n"
         b"k, Calibration finished\r\n"]
    )  # fmt: skip
    robot.proximity.calibrate()
    assert fake.writes[-1] == b"K\n"


def test_calibration_that_never_finishes_is_a_timeout(robot_on) -> None:  # type: ignore[no-untyped-def]
    robot, _ = robot_on([b"k, Starting calibration - Remove any object in sensors range\r\n"])
    with pytest.raises(ego.errors.LinkTimeoutError, match="did not finish"):
        robot.proximity.calibrate()


# -- D -----------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("asked", "real"), [(1000, 1000), (950, 1000), (625, 625), (600, 625), (300, 10000 / 33),
                        (-600, -625), (0, 0), (1, 1), (1500, 1000)]
)  # fmt: skip
def test_the_wheels_turn_at_the_timer_quantised_speed(asked: int, real: float) -> None:
    """e_motors.c: the step period is 10000/|v| ticks of a 10 kHz timer, in whole ticks."""
    assert real_speed_steps(asked) == pytest.approx(real)


# -- b -----------------------------------------------------------------------------------------


def test_webots_firmware_has_no_battery(robot_on) -> None:  # type: ignore[no-untyped-def]
    """firmware.c: no case 'b' (the byte is skipped silently, so nothing would answer)."""
    robot, _ = robot_on([])
    with pytest.raises(UnsupportedDeviceError, match="'b'"):
        robot.battery.enable(STEP_MS)


# -- lines and rates ---------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("port", "firmware", "baud"),
    [("/dev/ttyS0", None, 230400), ("/dev/rfcomm0", None, 115200),
     ("/dev/ttyS0", Firmware.WEBOTS, 115200), ("/dev/rfcomm0", Firmware.GCTRONIC, 230400)],
)  # fmt: skip
def test_each_line_opens_at_its_firmware_rate(
    port: str, firmware: Firmware | None, baud: int
) -> None:
    """firmware.c: e_init_uart1() at 115200 only; Asercom.c: UART2 at 230400 in selector 10."""
    assert default_baud(port, firmware) == baud


def test_the_webots_face_reads_the_stock_firmwares_battery_flag() -> None:
    """Asercom.c 'b': [BATT_LOW, 0] on a robot older than rev 1.3; Webots' battery sensor
    calls read it where the firmware has it."""
    from ego.controller import Robot
    from ego.faces import default_robot, runtime
    from firmware_sim import Emulator

    with Emulator("gctronic", seed=1) as emu:
        default_robot.set_options(runtime.RunOptions(port=emu.path))
        try:
            robot = Robot()
            try:
                assert math.isnan(robot.batterySensorGetValue())
                robot.batterySensorEnable(32)
                assert robot.batterySensorGetSamplingPeriod() == 32
                robot.step(32)
                assert robot.batterySensorGetValue() == 1.0
                assert robot.core.battery.low is False
            finally:
                robot.cleanup()
        finally:
            default_robot.set_options(runtime.RunOptions())
