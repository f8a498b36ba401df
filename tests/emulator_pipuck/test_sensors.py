"""The chips the Pi reads directly on the e-puck2's bus: the MPU-9250, the VL53L0X, the
ground-sensor module; and the battery ADC's sysfs files."""

from __future__ import annotations

import math
import struct

from pipuck_harness import quiet_world

from firmware_sim.pipuck import PipuckEmulator
from firmware_sim.world import ROBOT_RADIUS_M, Block, Pose


def test_the_mpu9250_reads_gravity_and_turning_big_endian(epuck2, client_of):
    client = client_of(epuck2)
    assert client("bus(12).read_byte_data(0x68, 0x75)") == 0x71  # WHO_AM_I
    assert client("bus(12).read_byte_data(0x69, 0x75)") == {"errno": "EREMOTEIO"}
    acc = struct.unpack(">3h", bytes(client("bus(12).read_i2c_block_data(0x68, 0x3B, 6)")))
    assert acc == (0, 0, 16384)  # +1 g up at rest (e-puck2_imu.py:92)
    client("exchange(12, packet(-500, 500))")  # turn left on the spot
    gyro = struct.unpack(">3h", bytes(client("bus(12).read_i2c_block_data(0x68, 0x43, 6)")))
    rate = math.degrees(epuck2.world.velocity()[2])
    assert gyro[0] == gyro[1] == 0 and abs(gyro[2] - rate * 32768 / 250) <= 1
    client("bus(12).write_byte_data(0x68, 0x1B, 0x18)")  # +-2000 deg/s
    fast = struct.unpack(">3h", bytes(client("bus(12).read_i2c_block_data(0x68, 0x43, 6)")))
    assert abs(fast[2] - gyro[2] / 8) <= 1
    # One burst from INT_STATUS as the firmware reads it (mpu9250.c:248-249).
    burst = client("bus(12).read_i2c_block_data(0x68, 0x3A, 15)")
    assert burst[0] & 1 and burst[1:7] == list(struct.pack(">3h", *acc))


def test_the_tof_measures_the_ray_ahead_in_single_shot(epuck2, client_of):
    epuck2.world.blocks.append(Block(0.2, 0.0, 0.02, (200, 60, 60)))
    epuck2.world.place(Pose(0.0, 0.0, 0.0))
    client = client_of(epuck2)
    assert client("bus(12).read_byte_data(0x29, 0xC0)") == 0xEE  # model id
    client("bus(12).write_byte_data(0x29, 0x00, 0x01)")  # SYSRANGE_START, single shot
    assert client("bus(12).read_byte_data(0x29, 0x00)") & 1 == 0
    assert client("bus(12).read_byte_data(0x29, 0x13)") & 0x07  # a sample is ready
    result = client("bus(12).read_i2c_block_data(0x29, 0x14, 12)")
    mm = result[10] << 8 | result[11]  # vl53l0x_api.c:2418
    expected = (0.2 - 0.02 - ROBOT_RADIUS_M) * 1000
    assert abs(mm - expected) <= 1 and (result[0] & 0x78) >> 3 == 11
    client("bus(12).write_byte_data(0x29, 0x0B, 0x01)")  # clear the interrupt
    assert client("bus(12).read_byte_data(0x29, 0x13)") & 0x07 == 0
    # The NVM handshake a driver waits on, on page 7, never reads 0.
    client("bus(12).write_byte_data(0x29, 0xFF, 0x07)")
    client("bus(12).write_byte_data(0x29, 0x83, 0x00)")
    assert client("bus(12).read_byte_data(0x29, 0x83)") != 0
    client("bus(12).write_byte_data(0x29, 0x00, 0x01)")  # on page 7: not a start
    client("bus(12).write_byte_data(0x29, 0xFF, 0x00)")
    assert client("bus(12).read_byte_data(0x29, 0x13)") & 0x07 == 0


def test_the_ground_module_reads_the_floor_big_endian(epuck2, client_of):
    client = client_of(epuck2)
    data = bytes(client("bus(12).read_i2c_block_data(0x60, 0, 12)"))
    ground = struct.unpack(">3H", data[:6])
    assert list(ground) == epuck2.world.floor()
    assert struct.unpack(">3H", data[6:12]) == (1000, 1000, 1000)


def test_no_ground_module_means_nothing_at_0x60(client_of):
    with PipuckEmulator("epuck2", world=quiet_world(), ground_module=False) as emu:
        client = client_of(emu)
        assert client("bus(12).read_i2c_block_data(0x60, 0, 6)") == {"errno": "EREMOTEIO"}


def test_the_battery_files_give_the_voltage_the_way_gctronic_reads_them(epuck2):
    # battery/read-battery.py:40-48: volts = raw * scale / 500.
    base = epuck2.sysfs_root / "sys/bus/i2c/devices/11-0048/iio:device0"
    raw = float((base / "in_voltage0_raw").read_text())
    scale = float((base / "in_voltage0_scale").read_text())
    assert round(raw * scale / 500, 2) == 3.9
    epuck2.set_battery(3.5)
    assert round(float((base / "in_voltage0_raw").read_text()) * scale / 500, 2) == 3.5


def test_the_tof_in_back_to_back_mode_ranges_again_after_each_clear(epuck2, client_of):
    epuck2.world.blocks.append(Block(0.2, 0.0, 0.02, (200, 60, 60)))
    epuck2.world.place(Pose(0.0, 0.0, 0.0))
    client = client_of(epuck2)
    mm = "(lambda r: r[10] << 8 | r[11])(bus(12).read_i2c_block_data(0x29, 0x14, 12))"
    client("bus(12).write_byte_data(0x29, 0x00, 0x03)")  # start, back-to-back
    first = client(mm)
    epuck2.world.place(Pose(0.05, 0.0, 0.0))  # 5 cm closer
    assert client(mm) == first  # the sample stays until the interrupt is cleared
    client("bus(12).write_byte_data(0x29, 0x0B, 0x01)")
    assert client("bus(12).read_byte_data(0x29, 0x13)") & 0x07
    assert abs(client(mm) - (first - 50)) <= 1
