"""The chips a Pi-puck reads beside the e-puck's microcontroller, as data (no I/O).

Each :class:`Reader` says where a chip answers on the robot's I2C bus, how it is told
apart, what is written once it answered, which bytes a reading is and how they become
the values of ego's wire command for that family (so the device families decode them
as on every other robot). docs/protocol.md, "The Pi-puck", has the sources:

* MPU-9250 (e-puck2) at 0x68, or 0x69 when AD1 is high (GCtronic's
  ``e-puck2/e-puck2_imu.py:12-13, 33-39``): ACCEL_XOUT_H 0x3B and GYRO_XOUT_H 0x43, six
  bytes each, three big-endian int16 (``e-puck2_imu.py:140-149``); +-2 g (16384 a g) and
  +-250 deg/s (131 a deg/s) at power-on. WHO_AM_I (0x75) reads 0x71 [the chip's
  datasheet]. ego writes PWR_MGMT_1 (0x6B) = 0x01, its reset value (awake, best clock),
  so a chip some earlier program put to sleep answers.
* LSM330 (e-puck1 rev 1.3): the accelerometer at 0x1E and the gyro at 0x6A
  (``e-puck1/e-puck1_imu.c:63-83``), set up as that program does (0x20 = 0x9F and
  0x25 = 0x50 on the accelerometer; 0x20 = 0xCF, 0x21 = 0x20, 0x23 = 0x00, 250 deg/s, on
  the gyro); six bytes from 0x28 with bit 7 set (auto-increment), little-endian int16.
* VL53L0X ToF at 0x29 (``e-puck2/VL53L0X_example.py:35``); see :func:`tof_reader`.
* The ground module at 0x60: six bytes from register 0, three big-endian words
  (``ground-sensor/groundsensor.py:40-44``): :func:`ego.i2c.chips.decode_ground`.

The accelerometers' values become ``a``'s counts as the e-puck2 firmware scales its
own, ``((v >> 4) - (v >> 6)) + 2048`` (768 a g), x and y exchanged to the e-puck's axes
as epuck_ros2's driver does (``driver.cpp:315-320``) [inferred for the MPU-9250: no
source states its mounting]. The gyros' values become the e-puck2's gyro counts,
131.072 a deg/s.
"""

from __future__ import annotations

import struct
from collections.abc import Callable
from dataclasses import dataclass
from typing import Final

from ego.i2c.chips import decode_ground, legacy_counts

__all__ = [
    "GROUND",
    "LSM330_ACC",
    "LSM330_GYRO",
    "MPU9250_ACC",
    "MPU9250_GYRO",
    "Reader",
    "mpu_acc",
    "mpu_gyro",
]


@dataclass(frozen=True, slots=True)
class Reader:
    """One chip's reading on the robot's bus."""

    #: For messages: "MPU-9250", "ground module".
    name: str
    #: The 7-bit addresses it may answer at, tried in order.
    addresses: tuple[int, ...]
    #: (register, expected) that proves the chip is this one; None: an acknowledged read
    #: of the data is proof enough (the ground module has no identity register).
    identity: tuple[int, int] | None
    #: (register, value) written once it answered.
    setup: tuple[tuple[int, int], ...]
    #: The register a reading starts at and its length.
    register: int
    count: int
    #: The reading's bytes as the wire command's values.
    decode: Callable[[bytes], tuple[int, ...]]


def _swap(x: int, y: int, z: int) -> tuple[int, int, int]:
    return (y, x, z)


def mpu_acc(data: bytes) -> tuple[int, ...]:
    """MPU-9250 ACCEL_XOUT_H..ACCEL_ZOUT_L as ``a``'s counts (2048 at 0 g, 768 a g)."""
    return tuple(legacy_counts(v) for v in _swap(*struct.unpack(">3h", data)))


#: The MPU-9250's and the e-puck2 gyro's counts agree (131 and 131.072 a deg/s).
def mpu_gyro(data: bytes) -> tuple[int, ...]:
    """MPU-9250 GYRO_XOUT_H..GYRO_ZOUT_L as the e-puck2's gyro counts."""
    return _swap(*struct.unpack(">3h", data))


def _lsm_acc(data: bytes) -> tuple[int, ...]:
    return tuple(legacy_counts(v) for v in _swap(*struct.unpack("<3h", data)))


#: The LSM330's gyro at 250 deg/s: 8.75 mdps a count [its datasheet]; in 131.072 a deg/s.
_LSM_GYRO_SCALE: Final = 8.75e-3 * 131.072


def _lsm_gyro(data: bytes) -> tuple[int, ...]:
    x, y, z = _swap(*struct.unpack("<3h", data))
    return tuple(max(-32768, min(32767, round(v * _LSM_GYRO_SCALE))) for v in (x, y, z))


_MPU = (0x68, 0x69)
_MPU_WHO_AM_I = (0x75, 0x71)
_MPU_AWAKE = ((0x6B, 0x01),)

MPU9250_ACC: Final = Reader("MPU-9250", _MPU, _MPU_WHO_AM_I, _MPU_AWAKE, 0x3B, 6, mpu_acc)
MPU9250_GYRO: Final = Reader("MPU-9250", _MPU, _MPU_WHO_AM_I, _MPU_AWAKE, 0x43, 6, mpu_gyro)
LSM330_ACC: Final = Reader(
    "LSM330 accelerometer", (0x1E,), (0x0F, 0x40), ((0x20, 0x9F), (0x25, 0x50)),
    0x28 | 0x80, 6, _lsm_acc,
)  # fmt: skip
LSM330_GYRO: Final = Reader(
    "LSM330 gyro", (0x6A,), (0x0F, 0xD4), ((0x20, 0xCF), (0x21, 0x20), (0x23, 0x00)),
    0x28 | 0x80, 6, _lsm_gyro,
)  # fmt: skip
GROUND: Final = Reader("ground module", (0x60,), None, (), 0, 6, decode_ground)
