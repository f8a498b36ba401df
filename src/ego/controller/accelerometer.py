"""Webots' ``Accelerometer``."""

from __future__ import annotations

from ego.controller.device import NAN as _NAN
from ego.controller.device import view
from ego.controller.sensor import Sensor

__all__ = ["Accelerometer"]

#: The accelerometer's lookupTable.
ACCELEROMETER_TABLE = (-100, -100, 0.003, 100, 100, 0.003)


@view("Accelerometer")
class Accelerometer(Sensor):
    def getLookupTable(self) -> list[float]:
        return list(ACCELEROMETER_TABLE)

    def getValues(self) -> list[float]:
        """x, y, z in m/s^2 (NaN while not enabled)."""
        if not self._readable():
            return [_NAN, _NAN, _NAN]
        return list(self._core.accelerometer.acceleration_mps2)

    value = property(lambda self: self.getValues())
    lookup_table = property(lambda self: self.getLookupTable())
