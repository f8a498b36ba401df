"""The e-puck2's IMU (MPU-9250) as the asercom layer reports it: accelerometer, gyro,
magnetometer and temperature, from the world's motion.

Chip set-up (MAIN:src/sensors/imu.c:332-334): accelerometer +-2 g, gyro +-250 deg/s, so
16384 counts a g (``GRAVITY -16384``, MAIN:src/epuck1x/a_d/advance_ad_scan/e_acc.h:17) and
32768/250 = 131.072 counts per deg/s (MAIN:src/sensors/mpu9250.c:10-16).

The firmware negates every accelerometer axis as it reads the chip (mpu9250.c:259-263), so
``acc_raw`` reads -1 g (-16384) on z at rest; the start-up calibration (e_acc_calibr,
MAIN:src/epuck1x/Asercom2.c:152/157 -> imu.c calibrate_acc) stores the resting readings
as offsets. The e-puck1-compatible values then follow e_acc.c:17-50 exactly (arithmetic
shifts and all); their frame is the e-puck1's: x to the right, y backwards (forward is
-y), z up (MAIN:src/epuck1x/acc_gyro/e_lsm330.c:6-23).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from firmware_sim.world import World

__all__ = ["Imu", "e_acc_spheric"]

COUNTS_PER_G = 16384
GYRO_COUNTS_PER_DPS = 32768 / 250.0
#: e_acc.h:8, ``CST_RADIAN (180.0/3.1415)``.
CST_RADIAN = 180.0 / 3.1415
#: mpu9250.c:14, ``RAW16BITS_TO_TESLA (4912.0/32760.0)`` (microtesla per count).
MAG_UT_PER_COUNT = 4912.0 / 32760.0
#: The Earth's field the magnetometer sees, in microtesla: horizontal towards +y (north
#: in firmware_sim's worlds) and vertical (down). A mid-latitude figure [inferred: the
#: sources give none].
EARTH_HORIZONTAL_UT = 21.0
EARTH_DOWN_UT = 43.0


class AccRaw(NamedTuple):
    """``imu_values.acc_raw``: the chip's counts, each axis negated (mpu9250.c:259-263)."""

    x: int
    y: int
    z: int


def _shrink(t: int) -> int:
    """e_acc.c:29 / :48, ``(t>>4) - (t>>6)``: 16-bit counts to about 768 a g."""
    return (t >> 4) - (t >> 6)


def _int16(v: float) -> int:
    return max(-32768, min(32767, int(round(v))))


def e_acc_spheric(x: int, y: int, z: int) -> tuple[float, float, float]:
    """e_acc.c:57-74, e_read_acc_spheric: magnitude, orientation, inclination (float32)."""
    f32 = np.float32
    magnitude = math.sqrt(float(f32(x * x + y * y + z * z)))
    horizontal = math.sqrt(float(f32(x * x + y * y)))
    inclination = 90.0 - float(f32(math.atan2(z, horizontal))) * CST_RADIAN
    if inclination < 5 or inclination > 160:
        orientation = 0.0
    else:
        orientation = float(f32(math.atan2(x, y))) * CST_RADIAN + 180.0
    return float(f32(magnitude)), float(f32(orientation)), float(f32(inclination))


class Imu:
    """The IMU of one robot in ``world``; ``magnetometer_on`` as the firmware left it."""

    #: The offsets calibrate_acc stores at rest on a level floor (imu.c:467-478).
    ACC_OFFSET = AccRaw(0, 0, -COUNTS_PER_G)

    def __init__(self, world: World, rng: np.random.Generator, temperature_c: float) -> None:
        self.world = world
        self._rng = rng
        self.temperature_c = temperature_c
        #: Whether mpu9250_magnetometer_setup has run (selector 15 at start, main.c:852,
        #: or binary -0x0F with 1, Asercom2.c:654-655); until then the external-sensor
        #: registers the firmware reads the field from hold 0.
        self.magnetometer_on = False

    def _noise(self, sigma: float) -> float:
        return float(self._rng.normal(0.0, sigma)) if self.world.noise else 0.0

    def acc_raw(self) -> AccRaw:
        """The firmware's acc_raw from the world's specific force.

        The world's accelerometer_raw(0, 16384) gives lateral (left positive, negated) on
        x, forward on y and 1 g up on z; in the e-puck1 frame that is f = (x, -y, z), and
        acc_raw = (-f_x, f_y, -f_z) makes e_get_acc read f (with the offsets above).
        """
        wx, wy, wz = self.world.accelerometer_raw(0, COUNTS_PER_G)
        return AccRaw(_int16(-wx), _int16(-wy), _int16(-wz))

    def e_get_acc(self) -> tuple[int, int, int]:
        """e_acc.c:17-32: offsets removed, z keeps gravity, about 768 a g, centred on 0."""
        raw, off = self.acc_raw(), self.ACC_OFFSET
        x = raw.x - off.x
        y = -(raw.y - off.y)
        z = raw.z - off.z + (-COUNTS_PER_G)  # e_acc.h:17, GRAVITY -16384
        return -_shrink(x), -_shrink(y), -_shrink(z)

    def e_get_acc_filtered(self) -> tuple[int, int, int]:
        """e_acc.c:34-50 (filter size 1): no offsets, signs flipped on x and z, +2048."""
        raw = self.acc_raw()
        return (_shrink(-raw.x) + 2048, _shrink(raw.y) + 2048, _shrink(-raw.z) + 2048)

    def gyro_raw(self) -> tuple[int, int, int]:
        """The chip's gyro counts: the world only turns about z (counter-clockwise +)."""
        _, _, wz = self.world.velocity()
        dps = math.degrees(wz)
        return (
            _int16(self._noise(2.0)),
            _int16(self._noise(2.0)),
            _int16(dps * GYRO_COUNTS_PER_DPS + self._noise(2.0)),
        )

    def gyro(self) -> tuple[int, int, int]:
        """e_lsm330.c:43-49, getAllAxesGyro: x and y exchanged, x negated; the offsets
        calibrate_gyro took at start (main.c:132) are the ideal chip's zero."""
        x, y, z = self.gyro_raw()
        return -y, x, z

    def magnetic_field(self) -> tuple[float, float, float]:
        """imu.c:588-592: the last field in microtesla (float), 0 until set up.

        The field is the Earth's (above) in the robot's frame, x forward, y left, z up
        [axes inferred], in whole counts of mpu9250.c:14.
        """
        if not self.magnetometer_on:
            return (0.0, 0.0, 0.0)
        nx, ny, _ = self.world.compass_vector()
        field = (EARTH_HORIZONTAL_UT * nx, EARTH_HORIZONTAL_UT * ny, -EARTH_DOWN_UT)
        counts = [round(b / MAG_UT_PER_COUNT + self._noise(2.0)) for b in field]
        return tuple(float(np.float32(c * MAG_UT_PER_COUNT)) for c in counts)  # type: ignore[return-value]

    def temperature(self) -> int:
        """e_lsm330.c:63-65, ``(signed char)get_temperature()``: whole degrees, truncated."""
        return max(-128, min(127, int(self.temperature_c)))
