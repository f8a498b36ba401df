"""The e-puck2's three-axis gyro, ``gyro`` (wire command -'g').

The firmware answers the IMU's raw rates less their calibrated offsets, x, y, z as i16,
131.072 counts per deg/s at +-250 deg/s (MAIN:src/epuck1x/Asercom2.c:822-839,
acc_gyro/e_lsm330.c:29-49). Webots' e-puck2 gyro has the lookup table
``-13.315805 -100000 0.003, 13.315805 100000 0.003``: 7509.9 per rad/s, which is those
same counts (131.072 x 180/pi), so the Webots face reports them as they are.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from ego.devices.base import Sensor, Verdict, out_of_range
from ego.devices.table import RAW, TABLE, Series
from ego.seam.batch import Request
from ego.seam.profile import Command, Profile

__all__ = ["GYRO_COUNTS_PER_DEG_S", "Gyro"]

#: e_lsm330.c:29 (and the MPU-9250's +-250 deg/s range): counts per degree a second.
GYRO_COUNTS_PER_DEG_S = 131.072


@TABLE.declare(
    "gyro",
    webots_rank=10,
    series=Series("gyro", "deg/s", ("x", "y", "z"), (RAW, 131.072)),
)
class Gyro(Sensor):
    """Turning rates about x, y, z, raw counts (131.072 per deg/s); z is counter-clockwise.

    >>> robot.gyro.enable(32)                            # doctest: +SKIP
    >>> robot.step(32); robot.gyro.rates_rad_s[2]
    0.52
    """

    family = "gyro"
    command = Command.GYRO_RAW
    #: Webots' e-puck gyro (E-puck.proto): rad/s in, counts out, 1:1 with the firmware's.

    def __init__(self, profile: Profile) -> None:
        super().__init__(profile)
        self._counts: tuple[int, int, int] = (0, 0, 0)

    @property
    def member_names(self) -> tuple[str, ...]:
        return self.served_names()

    def validate(self, request: Request, values: Sequence[float], now_s: float) -> Verdict:
        return Verdict(out_of_range(self.family, values, -32768, 32767))

    def take(self, values: Sequence[float]) -> None:
        x, y, z = (int(v) for v in values[:3])
        self._counts = (x, y, z)

    @property
    def values(self) -> tuple[int, int, int]:
        """x, y, z in raw counts (Webots' gyro values)."""
        self.require_values()
        return self._counts

    @property
    def rates_rad_s(self) -> tuple[float, float, float]:
        """x, y, z in rad/s."""
        x, y, z = (math.radians(c / GYRO_COUNTS_PER_DEG_S) for c in self.values)
        return (x, y, z)

    def readings(self) -> list[float] | None:
        return [float(c) for c in self._counts] if self.has_values else None
