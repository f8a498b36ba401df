"""Webots' ``Gyro``."""

from __future__ import annotations

from ego.controller.device import NAN as _NAN
from ego.controller.device import view
from ego.controller.sensor import Sensor
from ego.faces.webots_model import webots_model

__all__ = ["Gyro"]


@view("Gyro")
class Gyro(Sensor):
    """Webots' Gyro: x, y, z through the model's lookup table (NaN while not enabled)."""

    def getValues(self) -> list[float]:
        family = self._core.device(self._name)
        readings = family.readings() if self._readable() else None
        if readings is None:
            return [_NAN, _NAN, _NAN]
        return [float(v) for v in readings]

    def getLookupTable(self) -> list[float]:
        return list(webots_model(self._core.device(self._name)).lookup or ())

    value = property(lambda self: self.getValues())
    lookup_table = property(lambda self: self.getLookupTable())
