"""The Overo's own I2C bus: the floor sensors and a rev 1.3's accelerometer, which the stock
firmware in Overo mode leaves to Linux (docs/protocol.md, "The Overo's own I2C bus").

GCtronic, main_c.c:110-122: in selector 10 the firmware disables its I2C peripheral "to
let the gumstix extension be the master ... (camera, ground sensor, digital acc+gyro)";
Asercom.c:419-440 then serves ``M`` only `if (use_bt)`, and ``a`` answers zeros on a rev
1.3. ego reads both chips over i2c-dev, here over the emulator's model of the bus.
"""

from __future__ import annotations

import errno
import math
import struct
import subprocess
from itertools import pairwise
from pathlib import Path
from typing import Any

import pytest
from helpers import ego_command, emulator_of

import ego
from ego.backends.serial_line import robot_i2c
from ego.errors import OutOfRangeError, UnsupportedDeviceError
from ego.i2c.chips import (
    ACC_COUNTS_PER_G,
    decode_accelerometer,
    decode_ground,
    decode_lsm330,
    epuck_axes,
)
from ego.recording.reader import Recording
from firmware_sim import Emulator
from firmware_sim.floor import LineTrack
from firmware_sim.i2c import GroundModule, Lsm330, OveroBus
from firmware_sim.worlds import load_world

STEP_MS = 32
CONTROLLERS = Path(__file__).parents[1] / "faces" / "controllers"


class FixedWorld:
    """A world whose floor and accelerometer read fixed values (the chips' registers only)."""

    def __init__(self, floor: list[int], acc: tuple[int, int, int]) -> None:
        self._floor, self._acc = floor, acc

    def floor(self) -> list[int]:
        return list(self._floor)

    def accelerometer_raw(self, zero: int, per_g: int) -> tuple[int, int, int]:
        assert (zero, per_g) == (0, 16384)  # the LSM330's counts, no offset
        return self._acc


# -- the registers, as the emulator writes them and ego reads them --------------------------


def test_ground_registers_are_big_endian_pairs_left_centre_right() -> None:
    """Asercom.c:424-428 sends register j+1 then j (low byte first on the line), so register
    2k is sensor k's high byte; gctronic/Pi-puck groundsensor.py: d[1] + (d[0] << 8)."""
    module = GroundModule(FixedWorld([0x0123, 0x0456, 0x0789], (0, 0, 0)))  # type: ignore[arg-type]
    data = module.read(0, 6)
    assert data == bytes([0x01, 0x23, 0x04, 0x56, 0x07, 0x89])
    assert decode_ground(data) == (0x0123, 0x0456, 0x0789)
    assert struct.unpack("<3H", data) != (0x0123, 0x0456, 0x0789)  # the order matters


def test_lsm330_outputs_are_little_endian_int16_with_x_and_y_exchanged() -> None:
    """e_lsm330.c:146-154: x = arr[1] << 8 | arr[0]...; e_acc.c:170-175: the e-puck's x is
    the chip's y and its y the chip's x, scaled ((v >> 4) - (v >> 6)) + 2048."""
    x_epuck, y_epuck, z = 1000, -2000, 16384
    chip = Lsm330(FixedWorld([0, 0, 0], (x_epuck, y_epuck, z)))  # type: ignore[arg-type]
    data = chip.read(0x28 | 0x80, 6)
    assert data == struct.pack("<3h", y_epuck, x_epuck, z)  # the chip's own axes
    assert decode_lsm330(data) == (y_epuck, x_epuck, z)
    assert epuck_axes(decode_lsm330(data)) == (x_epuck, y_epuck, z)
    # (1000 >> 4) - (1000 >> 6) = 62 - 15; (-2000 >> 4) - (-2000 >> 6) = -125 + 32 (C's >>)
    assert decode_accelerometer(data) == (2048 + 47, 2048 - 93, 2048 + 768)
    assert ACC_COUNTS_PER_G == 768  # one g, 16384 counts at +-2 g, in the firmware's scale


def test_lsm330_steps_through_registers_only_with_bit_7() -> None:
    chip = Lsm330(FixedWorld([0, 0, 0], (0x0102, 0x0304, 0x0506)))  # type: ignore[arg-type]
    assert chip.read(0x0F, 1) == b"\x40"  # WHO_AM_I_A
    assert chip.read(0x28, 3) == bytes([0x04] * 3)  # OUT_X_L_A again and again
    assert chip.read(0xA8, 3) == bytes([0x04, 0x03, 0x02])


def test_an_absent_chip_does_not_acknowledge() -> None:
    bus = OveroBus(load_world("arena", 1), ground_module=False, rev13=False)
    for address in (0x60, 0x1E):
        with pytest.raises(OSError) as info:
            bus.read_block(address, 0, 1)
        assert info.value.errno == errno.EREMOTEIO


def test_the_emulator_hands_the_bus_to_the_overo_only_in_selector_10() -> None:
    with Emulator("gctronic", seed=1) as overo, Emulator("gctronic", seed=1, selector=3) as bt:
        assert overo.i2c is not None and bt.i2c is None
    with Emulator("webots", seed=1) as webots:
        assert webots.i2c is None


# -- the families over the bus ------------------------------------------------------------


def test_the_floor_is_read_over_i2c_on_the_overo_and_follows_the_world() -> None:
    with ego.Robot("sim", firmware="gctronic", world="line-track", seed=1) as robot:
        robot.floor.enable(STEP_MS)
        assert robot.step(STEP_MS) == 0
        left, middle, right = robot.floor.values
        assert middle < 500 < min(left, right)  # the track's line under the middle sensor
        emulator = emulator_of(robot)
        assert emulator.i2c.transfers >= 2  # the probe and a reading
        assert all("M" not in record.commands for record in emulator.history)


def _gravity_over_i2c(robot: ego.Robot, emulator: Emulator) -> None:
    robot.accelerometer.enable(STEP_MS)
    assert robot.step(STEP_MS) == 0
    x, y, z = robot.accelerometer.acceleration_mps2
    assert (x, y, z) == pytest.approx((0.0, 0.0, 9.81), abs=0.2)
    assert robot.accelerometer.values[2] == pytest.approx(2048 + 768, abs=3)
    assert all("a" not in record.commands for record in emulator.history)


def test_a_rev_1_3_accelerometer_reads_gravity_over_i2c() -> None:
    """Asercom.c:268-276: `a` answers zeros in Overo mode on a rev 1.3; the LSM330 is read
    (``--firmware gctronic``: the revision is not asked, the chip is probed)."""
    with ego.Robot("sim", firmware="gctronic", rev13=True, seed=1) as robot:
        _gravity_over_i2c(robot, emulator_of(robot))


def test_a_rev_1_3_told_by_its_battery_reply_reads_it_over_i2c_too() -> None:
    with Emulator("gctronic", seed=1, rev13=True) as emu, ego.Robot(emu.path, i2c=emu.i2c) as robot:
        assert robot.channel.profile.rev13 is True  # a and A are off the line
        _gravity_over_i2c(robot, emu)


def test_a_refused_spherical_mode_leaves_the_accelerometer_on_i2c() -> None:
    """Spherical values are the dsPIC's own (`A`), which a rev 1.3 in Overo mode lacks."""
    with Emulator("gctronic", seed=1, rev13=True) as emu, ego.Robot(emu.path, i2c=emu.i2c) as robot:
        robot.accelerometer.enable(STEP_MS)
        with pytest.raises(UnsupportedDeviceError, match="'A'"):
            robot.accelerometer.enable(STEP_MS, mode="spherical")
        assert robot.step(STEP_MS) == 0  # still raw, still over I2C
        assert robot.accelerometer.acceleration_mps2[2] == pytest.approx(9.81, abs=0.2)


def test_an_older_robot_on_the_overo_keeps_its_analog_accelerometer_on_the_line() -> None:
    with ego.Robot("sim", firmware="gctronic", seed=1) as robot:  # no LSM330 answers
        robot.accelerometer.enable(STEP_MS)
        assert robot.step(STEP_MS) == 0
        assert robot.accelerometer.values[2] == pytest.approx(2800, abs=10)  # 0 g 2000, 800/g
        assert robot.accelerometer.acceleration_mps2[2] == pytest.approx(9.81, abs=0.2)
        assert any("a" in record.commands for record in emulator_of(robot).history)


def test_a_chip_that_stops_answering_disables_its_family() -> None:
    with ego.Robot("sim", firmware="gctronic", seed=1) as robot:
        robot.floor.enable(STEP_MS)
        assert robot.step(STEP_MS) == 0
        del emulator_of(robot).i2c.chips[0x60]  # the module unplugged mid-run
        with pytest.raises(UnsupportedDeviceError, match=r"ground module at 0x60 .* stopped"):
            robot.step(STEP_MS)
        assert not robot.floor.enabled


class FlakyBus:
    """The emulator's bus, failing its next ``failures`` transfers (a bus held for a moment
    by a restarting dsPIC)."""

    def __init__(self, inner: OveroBus, failures: int) -> None:
        self.inner, self.failures, self.name = inner, failures, inner.name

    def _glitch(self) -> None:
        if self.failures > 0:
            self.failures -= 1
            raise OSError(errno.EAGAIN, "arbitration lost")

    def read_block(self, address: int, register: int, count: int) -> bytes:
        self._glitch()
        return self.inner.read_block(address, register, count)

    def write_byte_data(self, address: int, register: int, value: int) -> None:
        self._glitch()
        self.inner.write_byte_data(address, register, value)

    def close(self) -> None:
        self.inner.close()


def test_a_glitch_in_a_step_is_read_again(overo_emulator: Emulator) -> None:
    assert overo_emulator.i2c is not None
    bus = FlakyBus(overo_emulator.i2c, 0)
    with ego.Robot(overo_emulator.path, i2c=bus) as robot:
        robot.floor.enable(STEP_MS)
        bus.failures = 2  # fewer than the attempts a step makes
        assert robot.step(STEP_MS) == 0
        assert robot.floor.enabled and min(robot.floor.values) > 0


def test_a_chip_that_missed_its_probe_is_probed_again_at_the_next_enable(
    overo_emulator: Emulator,
) -> None:
    assert overo_emulator.i2c is not None
    bus = FlakyBus(overo_emulator.i2c, 1)
    with ego.Robot(overo_emulator.path, i2c=bus) as robot:
        with pytest.raises(UnsupportedDeviceError, match="arbitration lost"):
            robot.floor.enable(STEP_MS)
        robot.floor.enable(STEP_MS)  # the bus is free again
        assert robot.step(STEP_MS) == 0
        assert robot.floor.has_values


# -- no device there: the error names the way out ----------------------------------------------


def test_no_ground_module_on_the_bus_names_the_way_out() -> None:
    robot = ego.Robot("sim", firmware="gctronic", ground_module=False, seed=1)
    with robot, pytest.raises(UnsupportedDeviceError) as info:
        robot.floor.enable(STEP_MS)
    message = str(info.value)
    assert "floor sensors gs0..gs2" in message and "nothing answers at 0x60" in message
    assert "over Bluetooth (selector 3) the stock firmware serves them with M" in message


def test_a_port_that_does_not_reach_the_bus_names_the_way_out(overo_emulator: Emulator) -> None:
    with ego.Robot(overo_emulator.path) as robot:  # a pty: nothing of the robot's I2C
        with pytest.raises(UnsupportedDeviceError) as info:
            robot.floor.enable(STEP_MS)
        assert not robot.floor.enabled
    message = str(info.value)
    assert f"which {overo_emulator.path} does not reach" in message
    assert "run the controller on the robot" in message and "with M" in message


def test_a_missing_i2c_device_file_names_the_way_out(
    overo_emulator: Emulator, tmp_path: Path
) -> None:
    """The real bus class (smbus2) on a /dev/i2c-N that does not exist."""
    missing = tmp_path / "i2c-3"
    robot = ego.Robot(overo_emulator.path, i2c_bus=str(missing))
    with robot, pytest.raises(UnsupportedDeviceError) as info:
        robot.floor.enable(STEP_MS)
    message = str(info.value)
    assert f"the ground module on {missing} (not found: " in message
    assert "No such file or directory" in message


def test_a_rev_1_3_accelerometer_out_of_reach_names_the_way_out() -> None:
    with Emulator("gctronic", seed=1, rev13=True) as emu, ego.Robot(emu.path) as robot:
        assert robot.channel.profile.rev13 is True  # told by b: a is not on the line
        with pytest.raises(UnsupportedDeviceError) as info:
            robot.accelerometer.enable(STEP_MS)
    message = str(info.value)
    assert "the rev 1.3 accelerometer from the LSM330" in message
    assert "the stock firmware serves it with a" in message


def test_zeros_on_the_line_name_the_bus_that_was_out_of_reach() -> None:
    """Firmware given, revision not asked: `a` goes out and its zeros are refused."""
    with (
        Emulator("gctronic", seed=1, rev13=True) as emu,
        ego.Robot(emu.path, firmware="gctronic") as robot,
    ):
        robot.accelerometer.enable(STEP_MS)
        with pytest.raises(UnsupportedDeviceError) as info:
            robot.step(STEP_MS)
    message = str(info.value)
    assert message.startswith("no accelerometer data on this robot")
    assert "does not reach" in message and "serves it with a" in message


# -- which bus a port reaches ----------------------------------------------------------------


@pytest.mark.parametrize(
    ("port", "bus", "expected"),
    [
        ("/dev/ttyS0", None, "/dev/i2c-3"),  # ego runs on the Overo
        ("/dev/ttyO2", None, "/dev/i2c-3"),
        ("/dev/ttyUSB0", None, None),  # a PC: its buses are not the robot's
        ("/dev/rfcomm0", None, None),
        ("/dev/ttyUSB0", 2, "/dev/i2c-2"),
        ("/dev/ttyS0", "1", "/dev/i2c-1"),
        ("/dev/ttyS0", "/dev/i2c-7", "/dev/i2c-7"),
        ("/dev/ttyS0", "none", None),
    ],
)
def test_the_robot_i2c_bus_of_a_serial_port(port: str, bus: Any, expected: str | None) -> None:
    access = robot_i2c(port, bus)
    assert (access.name if access is not None else None) == expected


@pytest.mark.parametrize("bus", ["i2c-3", -1, 256, 3.0, True])
def test_a_bad_i2c_bus_is_refused(bus: Any) -> None:
    with pytest.raises(OutOfRangeError, match="I2C bus"):
        robot_i2c("/dev/ttyS0", bus)


# -- the line follower, unchanged, on the Overo's line ---------------------------------------


def test_a_line_follower_follows_the_line_on_the_overo_over_i2c(tmp_path: Path) -> None:
    """ego run --port sim --firmware gctronic: gs0..gs2 come over the emulated I2C bus; the
    check is test_worlds.py's line follower's, on the poses the recording keeps."""
    run = subprocess.run(
        [*ego_command(), "run", "--port", "sim", "--firmware", "gctronic", "--world",
         "line-track", "--seed", "1", "--duration", "6", "--record", "run.mcap",
         str(CONTROLLERS / "line_follower.py")],
        capture_output=True, text=True, cwd=tmp_path, timeout=120,
    )  # fmt: skip
    assert run.returncode == 0, run.stderr
    recording = Recording.open(tmp_path / "run.mcap")
    assert recording.metadata["firmware"] == "gctronic"
    track = load_world("line-track", 1).floor_pattern
    assert isinstance(track, LineTrack)
    poses = [sample["truth"] for sample in recording.samples]
    assert len(poses) > 100
    worst = max(float(track.distance(x, y)) for x, y, _ in poses)
    travelled = sum(math.hypot(b[0] - a[0], b[1] - a[1]) for a, b in pairwise(poses))
    assert travelled > 0.15  # it moved along the track ...
    assert worst < 0.025, worst  # ... and its centre never left the line's neighbourhood
