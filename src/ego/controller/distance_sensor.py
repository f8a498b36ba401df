"""Webots' ``DistanceSensor``: ps0..ps7 proximity, gs0..gs2 floor, the e-puck2's tof."""

from __future__ import annotations

from typing import ClassVar

from ego.controller.device import view
from ego.controller.sensor import _ValueSensor
from ego.faces.webots_model import webots_model

__all__ = ["DistanceSensor"]

# Webots' E-puck PROTO (projects/robots/gctronic/e-puck/protos), what its devices report.
#: E-puckDistanceSensor's lookupTable: distance (m), value, noise; rows flattened.
PROXIMITY_TABLE = (
    0, 4095, 0.002, 0.005, 2133.33, 0.003, 0.01, 1465.73, 0.007, 0.015, 601.46, 0.0406,
    0.02, 383.84, 0.01472, 0.03, 234.93, 0.0241, 0.04, 158.03, 0.0287, 0.05, 120, 0.04225,
    0.06, 104.09, 0.03065, 0.07, 67.19, 0.04897,
)  # fmt: skip
PROXIMITY_APERTURE_RAD = 0.1


@view("DistanceSensor")
class DistanceSensor(_ValueSensor):
    """ps0..ps9 proximity and gs0..gs2 floor sensors: raw values, as Webots' e-puck gives."""

    _table = PROXIMITY_TABLE
    GENERIC = 0
    INFRA_RED = 1
    SONAR = 2
    LASER = 3

    _TYPES: ClassVar[dict[str, int]] = {
        "generic": GENERIC, "infra-red": INFRA_RED, "sonar": SONAR, "laser": LASER
    }  # fmt: skip

    def getMinValue(self) -> float:
        """The table's smallest value, as Webots gives it."""
        return min(self.getLookupTable()[1::3])

    def getMaxValue(self) -> float:
        return max(self.getLookupTable()[1::3])

    def getAperture(self) -> float:
        own = webots_model(self._array_family()).aperture_rad
        return PROXIMITY_APERTURE_RAD if own is None else own

    def getType(self) -> int:
        own = webots_model(self._array_family()).sensor_type
        return self.INFRA_RED if own is None else self._TYPES[own]

    min_value = property(lambda self: self.getMinValue())
    max_value = property(lambda self: self.getMaxValue())
    aperture = property(lambda self: self.getAperture())
    type = property(lambda self: self.getType())
