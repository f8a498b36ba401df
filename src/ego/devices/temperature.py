"""The e-puck2's temperature (the IMU's, in the "all sensors" packet).

The firmware sends the IMU's temperature as a signed byte, whole degrees Celsius
(MAIN:src/epuck1x/Asercom2.c:376-381, ``(signed char)`` of e_lsm330.c:63-65).
"""

from __future__ import annotations

from collections.abc import Sequence

from ego.devices.base import Verdict, out_of_range
from ego.devices.packet import PacketSensor
from ego.devices.table import TABLE, Series
from ego.seam.batch import Request

__all__ = ["Temperature"]


@TABLE.declare("temperature", webots_rank=12, series=Series("temperature", "°C", ("temperature",)))
class Temperature(PacketSensor):
    """The robot's temperature in °C (whole degrees).

    >>> robot.temperature.enable(1000)                   # doctest: +SKIP
    >>> robot.step(64); robot.temperature.celsius
    30
    """

    family = "temperature sensor"
    fields = slice(12, 13)

    def validate(self, request: Request, values: Sequence[float], now_s: float) -> Verdict:
        return Verdict(out_of_range(self.family, values[self.fields], -40, 85))

    @property
    def celsius(self) -> int:
        return int(self.packet_values[0])
