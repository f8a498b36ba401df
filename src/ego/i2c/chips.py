"""The e-puck's chips on the Overo's I2C bus: addresses, registers and decoding (no I/O).

docs/protocol.md, "The Overo's own I2C bus", has the sources. Addresses here are 7-bit
(the dsPIC library writes them 8-bit: 0xC0 is 0x60, 0x3C is 0x1E).

* The ground module at 0x60: six registers from 0, three big-endian words, left, centre,
  right (register 2k is sensor k's high byte).
* The LSM330 accelerometer of an e-puck rev 1.3 at 0x1E: WHO_AM_I (0x0F) reads 0x40; six
  bytes from OUT_X_L_A (0x28, bit 7 set for auto-increment), three little-endian int16,
  16384 a g at the default +-2 g. The firmware exchanges x and y to keep the older
  robots' axes, and scales each to 12 bits as ``((v >> 4) - (v >> 6)) + 2048``: ego
  does the same, so a reading over I2C means what ``a`` means over Bluetooth.
"""

from __future__ import annotations

import struct
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from types import MappingProxyType

__all__ = [
    "ACC_COUNTS_PER_G",
    "ACC_ZERO_COUNTS",
    "CHIPS",
    "GROUND_ADDRESS",
    "LSM330_ACC_ADDRESS",
    "LSM330_WHO_AM_I",
    "Chip",
    "decode_accelerometer",
    "decode_ground",
    "decode_lsm330",
    "epuck_axes",
    "legacy_counts",
]

GROUND_ADDRESS = 0x60
GROUND_FIRST_REGISTER = 0

LSM330_ACC_ADDRESS = 0x1E
WHO_AM_I_A = 0x0F
LSM330_WHO_AM_I = 0x40
CTRL_REG5_A = 0x20
CTRL_REG7_A = 0x25
OUT_X_L_A = 0x28
#: Set on the register of a multi-byte read: the LSM330 then steps through the registers.
AUTO_INCREMENT = 0x80
#: What the firmware writes at start-up (e_lsm330.c, initAccAndGyro): 1600 Hz, BDU, x y z
#: on; auto-increment. ego writes the same, so as not to depend on the firmware's boot.
LSM330_SETUP = ((CTRL_REG5_A, 0x9F), (CTRL_REG7_A, 0x50))
#: One g at +-2 g full scale (gctronic/Pi-puck e-puck1_imu.c: GRAVITY_LSM330 16384).
LSM330_PER_G = 16384

#: 0 g of the firmware's 12-bit scaling, and one g in it: (16384 >> 4) - (16384 >> 6).
ACC_ZERO_COUNTS = 2048
ACC_COUNTS_PER_G = (LSM330_PER_G >> 4) - (LSM330_PER_G >> 6)


def decode_ground(data: bytes) -> tuple[int, int, int]:
    """Left, centre, right from the ground module's registers 0..5 (big-endian pairs)."""
    left, centre, right = struct.unpack(">3H", data)
    return (left, centre, right)


def decode_lsm330(data: bytes) -> tuple[int, int, int]:
    """The LSM330's own x, y, z from OUT_X_L_A..OUT_Z_H_A (little-endian int16)."""
    x, y, z = struct.unpack("<3h", data)
    return (x, y, z)


def epuck_axes(raw: tuple[int, int, int]) -> tuple[int, int, int]:
    """The chip's axes as the e-puck's: x and y exchanged (e_lsm330.c:6-18, e_acc.c:170-175)."""
    x, y, z = raw
    return (y, x, z)


def legacy_counts(value: int) -> int:
    """A 16-bit reading in the older robots' 12-bit counts, as the firmware scales it."""
    return ((value >> 4) - (value >> 6)) + ACC_ZERO_COUNTS


def decode_accelerometer(data: bytes) -> tuple[int, int, int]:
    """The six LSM330 bytes as the e-puck's x, y, z counts (``a``'s units on a rev 1.3)."""
    x, y, z = (legacy_counts(v) for v in epuck_axes(decode_lsm330(data)))
    return (x, y, z)


@dataclass(frozen=True, slots=True)
class Chip:
    """One chip on the bus: where it answers, how it is told apart, what a reading is."""

    #: The key the profiles use (``Profile.i2c``): "ground module", "LSM330".
    name: str
    #: Its 7-bit address.
    address: int
    #: The devices it serves, for messages ("gs0..gs2").
    devices: str
    #: (register, expected value) that proves the chip is this one; None: an acknowledged
    #: read of its data is proof enough (the ground module has no identity register).
    identity: tuple[int, int] | None
    #: (register, value) written once it answered.
    setup: tuple[tuple[int, int], ...]
    #: The register a reading starts at and its length.
    data_register: int
    data_count: int
    #: The reading's bytes as the family's values (the serial command's units).
    decode: Callable[[bytes], tuple[int, ...]]
    #: The other way to these devices, for the message when the bus does not reach them.
    elsewhere: str
    #: For an accelerometer: 0 g and counts a g of the decoded values.
    acc_scale: tuple[int, int] | None = None


#: The chips the stock firmware leaves to the Overo, by the name ``Profile.i2c`` gives.
CHIPS: Mapping[str, Chip] = MappingProxyType(
    {
        "ground module": Chip(
            "ground module", GROUND_ADDRESS, "the floor sensors gs0..gs2", None, (),
            GROUND_FIRST_REGISTER, 6, decode_ground,
            "over Bluetooth (selector 3) the stock firmware serves them with M",
        ),
        "LSM330": Chip(
            "LSM330", LSM330_ACC_ADDRESS, "the rev 1.3 accelerometer",
            (WHO_AM_I_A, LSM330_WHO_AM_I), LSM330_SETUP,
            OUT_X_L_A | AUTO_INCREMENT, 6, decode_accelerometer,
            "over Bluetooth (selector 3) the stock firmware serves it with a",
            (ACC_ZERO_COUNTS, ACC_COUNTS_PER_G),
        ),
    }
)  # fmt: skip
