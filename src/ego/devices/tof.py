"""The e-puck2's time-of-flight distance sensor, ``tof`` (wire command -0x0D).

The VL53L0X in the e-puck2's front measures up to about 2 m and the firmware answers its
last range in millimetres (MAIN:src/epuck1x/Asercom2.c:612-621, ``VL53L0X_get_dist_mm``).
Webots' e-puck2 (E-puck.proto, version "2") has it as a DistanceSensor ``tof`` (aperture
0.44 rad) whose lookup table maps 0..2 m to 19.8..2000: :func:`webots_value` turns the
robot's millimetres into that.
"""

from __future__ import annotations

from typing import ClassVar

from ego.devices.base import ArraySensor
from ego.seam.profile import Command

__all__ = ["TOF_APERTURE_RAD", "TOF_LOOKUP", "TofSensor", "webots_value"]

#: Webots' E-puck.proto (version "2"), ``tof``: lookupTable [0 19.8 0, 2 2000 0] (m -> value).
TOF_LOOKUP: tuple[tuple[float, float], tuple[float, float]] = ((0.0, 19.8), (2.0, 2000.0))
TOF_APERTURE_RAD = 0.44


def webots_value(distance_mm: float) -> float:
    """What Webots' ``tof`` reads at ``distance_mm``: the lookup table, held at its ends."""
    (d0, v0), (d1, v1) = TOF_LOOKUP
    distance_m = min(max(distance_mm / 1000.0, d0), d1)
    return v0 + (distance_m - d0) * (v1 - v0) / (d1 - d0)


class TofSensor(ArraySensor):
    """The distance to what is in front, in mm (about 0..2000; 8190 when nothing is in range).

    >>> robot.tof.enable(100)                            # doctest: +SKIP
    >>> robot.step(100); robot.tof.value("tof")
    412
    """

    family = "ToF distance sensor"
    table_family = "tof"
    command = Command.TOF
    #: The VL53L0X answers 8190 (8191 at most) when nothing reflects (its no-target value).
    value_range: ClassVar[tuple[int, int]] = (0, 8191)
    webots_lookup = (*TOF_LOOKUP[0], 0.0, *TOF_LOOKUP[1], 0.0)
    webots_aperture_rad = TOF_APERTURE_RAD
    webots_sensor_type = "generic"

    def webots_value(self, reading: float) -> float:
        """The millimetres as Webots' ``tof`` reports them (its lookup table)."""
        return webots_value(reading)

    @property
    def member_names(self) -> tuple[str, ...]:
        return self.served_names()

    @property
    def distance_mm(self) -> int:
        """The last distance in mm."""
        return self.values[0]
