"""The e-puck's I2C bus as the Overo sees it in selector 10: the ground module and a rev
1.3's LSM330 accelerometer, answering register reads from the world.

Written from the chips' register maps (docs/protocol.md, "The Overo's own I2C bus"),
independently of ``ego.i2c``, so that a mistake in ego's decoding shows up as a test
failure instead of being mirrored here:

* the ground module at 0x60 keeps left, centre, right as big-endian words in registers
  0..5 (register 2k is sensor k's high byte), and steps through them on a block read;
* the LSM330's accelerometer at 0x1E answers WHO_AM_I (0x0F) with 0x40, keeps x, y, z as
  little-endian int16 in 0x28..0x2D, 16384 a g at +-2 g, and steps through registers
  only when the register's bit 7 is set; powered down (CTRL_REG5_A's rate bits 0) its
  outputs read 0. Its x axis points forward and its y axis left: the firmware exchanges
  them into the e-puck's x (lateral) and y (forward).

An address nobody acknowledges raises OSError(EREMOTEIO), as the OMAP's I2C driver does.
"""

from __future__ import annotations

import errno
import os
import struct
import threading

from firmware_sim.world import World

__all__ = ["GroundModule", "Lsm330", "OveroBus"]

#: One g in the LSM330's counts at +-2 g full scale.
LSM330_PER_G = 16384
#: The registers the firmware writes at start-up, before it leaves the bus to the Overo
#: (e_lsm330.c, initAccAndGyro): 1600 Hz with x, y, z on; auto-increment on.
FIRMWARE_SETUP = {0x20: 0x9F, 0x25: 0x50}


class GroundModule:
    """The floor sensors' board at 0x60: three 16-bit readings, high byte first."""

    address = 0x60

    def __init__(self, world: World) -> None:
        self.world = world

    def registers(self) -> bytes:
        return struct.pack(">3H", *self.world.floor())

    def read(self, register: int, count: int) -> bytes:
        data = self.registers() + bytes(16)  # past the readings: zeros (cliff unmodelled)
        return data[register : register + count].ljust(count, b"\0")

    def write(self, register: int, value: int) -> None:
        pass  # nothing to configure


class Lsm330:
    """The LSM330's accelerometer at 0x1E, set up as the firmware leaves it."""

    address = 0x1E
    WHO_AM_I = 0x0F
    IDENTITY = 0x40
    CTRL_REG5_A = 0x20
    OUT_X_L_A = 0x28

    def __init__(self, world: World) -> None:
        self.world = world
        self.control = dict(FIRMWARE_SETUP)

    def _outputs(self) -> bytes:
        if not self.control.get(self.CTRL_REG5_A, 0) >> 4:
            return bytes(6)  # powered down
        # The world's reading on the e-puck's axes, in the chip's counts; the chip's x is
        # the e-puck's y and the other way round (the firmware exchanges them back).
        x_epuck, y_epuck, z = self.world.accelerometer_raw(0, LSM330_PER_G)
        return struct.pack("<3h", *(max(-32768, min(32767, v)) for v in (y_epuck, x_epuck, z)))

    def register(self, register: int, outputs: bytes) -> int:
        if register == self.WHO_AM_I:
            return self.IDENTITY
        if self.OUT_X_L_A <= register < self.OUT_X_L_A + 6:
            return outputs[register - self.OUT_X_L_A]
        return self.control.get(register, 0)

    def read(self, register: int, count: int) -> bytes:
        step = 1 if register & 0x80 else 0  # SUB(7): step through registers
        start = register & 0x7F
        outputs = self._outputs()  # one sample for the whole read (block data update)
        return bytes(self.register(start + i * step, outputs) for i in range(count))

    def write(self, register: int, value: int) -> None:
        self.control[register & 0x7F] = value & 0xFF


Chip = GroundModule | Lsm330


class OveroBus:
    """The bus with the chips this robot has fitted; every transfer under one lock."""

    def __init__(self, world: World, *, ground_module: bool = True, rev13: bool = False) -> None:
        chips: list[Chip] = []
        if ground_module:
            chips.append(GroundModule(world))
        if rev13:
            chips.append(Lsm330(world))
        self.chips = {chip.address: chip for chip in chips}
        self.name = "the emulator's I2C bus"
        self.transfers = 0
        self._lock = threading.Lock()

    def _chip(self, address: int) -> Chip:
        chip = self.chips.get(address)
        if chip is None:
            raise OSError(errno.EREMOTEIO, os.strerror(errno.EREMOTEIO))
        return chip

    def read_block(self, address: int, register: int, count: int) -> bytes:
        with self._lock:
            self.transfers += 1
            return self._chip(address).read(register, count)

    def write_byte_data(self, address: int, register: int, value: int) -> None:
        with self._lock:
            self.transfers += 1
            self._chip(address).write(register, value)

    def close(self) -> None:
        pass  # the emulator owns it
