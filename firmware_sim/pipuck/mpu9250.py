"""The e-puck2's MPU-9250 IMU at 0x68 (0x69 with AD0 high), read by the Pi directly.

Registers as the e-puck2 firmware's driver uses them (e-puck2_main-processor@d2e0dbb
src/sensors/mpu9250_registers.h:45-134, mpu9250.c): WHO_AM_I (0x75) answers 0x71
(mpu9250.c:239-243); PWR_MGMT_1 (0x6B) bit 7 resets the chip and clears itself
(mpu9250.c:71-90); GYRO_CONFIG (0x1B) and ACCEL_CONFIG (0x1C) bits 4:3 pick +-250..2000
deg/s and +-2..16 g (mpu9250.c:92-107); INT_STATUS (0x3A) and then the accelerometer
(0x3B-0x40), temperature (0x41-0x42) and gyro (0x43-0x48) follow in one burst, each a
big-endian int16 (mpu9250.c:245-280; GCtronic's Pi-side readers do the same:
gctronic/Pi-puck@73b8913 e-puck2/e-puck2_imu.py:14-18, 88-92, cyberbotics/epuck_ros2
mpu9250.cpp:22-57). The register pointer steps through the whole map on a burst.

The chip reads +1 g on z at rest: the firmware negates every axis to report -1 g
(mpu9250.c:259-268), and GCtronic's calibration subtracts +16384 from z
(e-puck2_imu.py:92). The values come from the world through the e-puck2 model's IMU
(firmware_sim.epuck2.imu), whose ``acc_raw`` is that negated reading. Temperature is
(T - 21) * 333.87 counts (the datasheet's formula, mpu9250.c:271).

[inferred] The gumstix firmware leaves the chip at power-on (its main() does not start
the IMU, e-puck2_main-processor@517ef07 src/main.c:403): PWR_MGMT_1 0x01 (awake), full
scales +-2 g and +-250 deg/s, the register map's reset values. Asleep (PWR_MGMT_1 bit
6) the outputs hold. The AK8963 magnetometer behind the chip's bypass is not modelled.
"""

from __future__ import annotations

import struct

from firmware_sim.epuck2.imu import Imu
from firmware_sim.pipuck.registers import RegisterTarget
from firmware_sim.world import World

__all__ = ["Mpu9250"]

GYRO_CONFIG, ACCEL_CONFIG, INT_STATUS, ACCEL_XOUT_H = 0x1B, 0x1C, 0x3A, 0x3B
PWR_MGMT_1, WHO_AM_I = 0x6B, 0x75
IDENTITY = 0x71
RESET_VALUES = {PWR_MGMT_1: 0x01, WHO_AM_I: IDENTITY}
TEMP_COUNTS_PER_C = 333.87


def _i16(value: float) -> int:
    return max(-32768, min(32767, int(round(value))))


class Mpu9250(RegisterTarget):
    """The IMU chip; ``imu`` is the e-puck2 model's (world motion, noise, temperature)."""

    def __init__(self, world: World, imu: Imu) -> None:
        super().__init__(RESET_VALUES)
        self.world = world
        self.imu = imu
        self._sample = bytes(14)

    def put(self, register: int, value: int) -> None:
        if register == WHO_AM_I:
            return  # read-only
        if register == PWR_MGMT_1 and value & 0x80:
            self.regs[:] = bytes(256)
            for reg, reset in RESET_VALUES.items():
                self.regs[reg] = reset
            return
        self.regs[register] = value

    def snapshot(self) -> None:
        if self.regs[PWR_MGMT_1] & 0x40:
            return  # asleep: the outputs hold
        acc_shift = self.regs[ACCEL_CONFIG] >> 3 & 3
        gyro_shift = self.regs[GYRO_CONFIG] >> 3 & 3
        acc = [-v / (1 << acc_shift) for v in self.imu.acc_raw()]
        gyro = [v / (1 << gyro_shift) for v in self.imu.gyro_raw()]
        temp = (self.imu.temperature_c - 21.0) * TEMP_COUNTS_PER_C
        self._sample = struct.pack(">7h", *(_i16(v) for v in (*acc, temp, *gyro)))

    def get(self, register: int) -> int:
        if register == INT_STATUS:
            return 0x01  # RAW_DATA_RDY_INT: a fresh sample every read
        if ACCEL_XOUT_H <= register < ACCEL_XOUT_H + 14:
            return self._sample[register - ACCEL_XOUT_H]
        return self.regs[register]
