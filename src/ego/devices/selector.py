"""The e-puck2's rotary selector, 0..15 (in the "all sensors" packet).

MAIN:src/epuck1x/Asercom2.c:448-450. The position chooses the firmware's mode at power-on
(8: asercom v2 over USB, 3: over Bluetooth); turned later, it is just a reading.
"""

from __future__ import annotations

from collections.abc import Sequence

from ego.devices.base import Verdict, out_of_range
from ego.devices.packet import PacketSensor
from ego.devices.table import TABLE, Series
from ego.seam.batch import Request

__all__ = ["Selector"]


@TABLE.declare("selector", webots_rank=14, series=Series("selector", "position", ("selector",)))
class Selector(PacketSensor):
    """The selector's position, 0..15.

    >>> robot.selector.enable(500)                       # doctest: +SKIP
    >>> robot.step(64); robot.selector.position
    8
    """

    family = "selector"
    fields = slice(41, 42)

    def validate(self, request: Request, values: Sequence[float], now_s: float) -> Verdict:
        return Verdict(out_of_range(self.family, values[self.fields], 0, 15))

    @property
    def position(self) -> int:
        return int(self.packet_values[0])
