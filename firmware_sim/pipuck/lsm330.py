"""The e-puck1 revision 1.3's LSM330: accelerometer at 0x1E, gyroscope at 0x6A.

Addresses: gctronic/Pi-puck@73b8913 e-puck1/e-puck1_imu.c:63, 78 (7-bit), the e-puck
library's 8-bit 0x3C and 0xD4 (gctronic/e-puck-library@4b2b492
library/acc_gyro/e_lsm330.c:27-28). Both read six bytes of little-endian int16 from
0x28 with bit 7 of the register set to step through them (e-puck1_imu.c:104-126;
e_lsm330.c:60-82, 146-149). The gyro's temperature is register 0x26, signed, one count a
degree (e_lsm330.c:228-230), and at +-250 deg/s a count is 8.75 mdeg/s
(e_lsm330.c:255-260). Chip axes: x forward, y left, z up (e_lsm330.c:6-17).

York's e-puck1 firmware never touches the chip, so it is as it powers up until the Pi
configures it (e-puck1_imu.c:63-96 writes CTRL_REG5_A 0x9F and CTRL_REG1_G 0xCF): the
accelerometer reuses firmware_sim.i2c's model with its control registers at reset.
[inferred from the datasheet's reset values]: the gyro's CTRL_REG1_G resets to 0x07
(power-down, outputs 0) and its WHO_AM_I (0x0F) reads 0xD4; CTRL_REG4_G bits 5:4 pick
250/500/2000 deg/s.
"""

from __future__ import annotations

import math
import struct
from typing import Protocol

import numpy as np

from firmware_sim.i2c import Lsm330
from firmware_sim.world import World

__all__ = ["Lsm330Gyro", "SubAddressed", "lsm330_accelerometer", "lsm330_gyro"]

ACCELEROMETER_ADDRESS = 0x1E
GYRO_ADDRESS = 0x6A

GYRO_MDPS_PER_COUNT = {0: 8.75, 1: 17.5, 2: 70.0, 3: 70.0}


class RegisterChip(Protocol):
    """A chip reached by register: ``read`` takes the register byte as sent (bit 7 set
    to step through registers)."""

    def read(self, register: int, count: int) -> bytes: ...

    def write(self, register: int, value: int) -> None: ...


class SubAddressed:
    """An I2C target over a :class:`RegisterChip`: a write's first byte is the register
    (bit 7: step on), the bytes after it are written from there; a read starts there."""

    def __init__(self, chip: RegisterChip, address: int) -> None:
        self.chip = chip
        self.address = address
        self.pointer = 0

    def write(self, data: bytes) -> None:
        if not data:
            return
        self.pointer = data[0]
        step = 1 if data[0] & 0x80 else 0
        for i, value in enumerate(data[1:]):
            self.chip.write(((data[0] & 0x7F) + i * step) & 0x7F, value)

    def read(self, count: int) -> bytes:
        return self.chip.read(self.pointer, count)

    def stop(self) -> None:
        pass


def lsm330_accelerometer(world: World) -> SubAddressed:
    """The accelerometer at 0x1E, powered down until configured (firmware_sim.i2c)."""
    chip = Lsm330(world)
    chip.control = {}  # no firmware set it up
    return SubAddressed(chip, ACCELEROMETER_ADDRESS)


def lsm330_gyro(world: World, rng: np.random.Generator) -> SubAddressed:
    """The gyroscope at 0x6A."""
    return SubAddressed(Lsm330Gyro(world, rng), GYRO_ADDRESS)


class Lsm330Gyro:
    """The gyroscope's registers: the world's turn rate about z, in counts of the
    chosen scale."""

    WHO_AM_I, IDENTITY = 0x0F, 0xD4
    CTRL_REG1_G, CTRL_REG4_G, OUT_TEMP_G, OUT_X_L_G = 0x20, 0x23, 0x26, 0x28

    def __init__(self, world: World, rng: np.random.Generator, temperature_c: int = 30) -> None:
        self.world = world
        self._rng = rng
        self.temperature_c = temperature_c
        self.control = {self.CTRL_REG1_G: 0x07}

    def write(self, register: int, value: int) -> None:
        self.control[register & 0x7F] = value & 0xFF

    def _outputs(self) -> bytes:
        if not self.control.get(self.CTRL_REG1_G, 0) & 0x08:
            return bytes(6)  # power-down
        scale = GYRO_MDPS_PER_COUNT[self.control.get(self.CTRL_REG4_G, 0) >> 4 & 3]
        _, _, wz = self.world.velocity()
        noise = [float(self._rng.normal(0.0, 2.0)) if self.world.noise else 0.0
                 for _ in range(3)]  # fmt: skip
        counts = [noise[0], noise[1], math.degrees(wz) * 1000.0 / scale + noise[2]]
        return struct.pack("<3h", *(max(-32768, min(32767, round(c))) for c in counts))

    def _register(self, register: int, outputs: bytes) -> int:
        if register == self.WHO_AM_I:
            return self.IDENTITY
        if register == self.OUT_TEMP_G:
            return self.temperature_c & 0xFF
        if self.OUT_X_L_G <= register < self.OUT_X_L_G + 6:
            return outputs[register - self.OUT_X_L_G]
        return self.control.get(register, 0)

    def read(self, register: int, count: int) -> bytes:
        step = 1 if register & 0x80 else 0
        outputs = self._outputs()  # one sample for the whole read
        return bytes(self._register(((register & 0x7F) + i * step) & 0x7F, outputs)
                     for i in range(count))  # fmt: skip
