"""The e-puck2's user button (wire command -0x0B).

MAIN:src/epuck1x/Asercom2.c:590-592 answers one byte, 1 while it is pressed. (Over USB
and Bluetooth the "all sensors" packet's byte 102 is reserved: only WiFi puts the button
there.)
"""

from __future__ import annotations

from collections.abc import Sequence

from ego.devices.base import ArraySensor, Verdict, out_of_range
from ego.devices.table import TABLE, Series
from ego.seam.batch import Request
from ego.seam.profile import Command

__all__ = ["Button"]


@TABLE.declare("button", webots_rank=13, series=Series("button", "pressed", ("button",)))
class Button(ArraySensor):
    """Whether the button is pressed.

    >>> robot.button.enable(64)                          # doctest: +SKIP
    >>> robot.step(64); robot.button.pressed
    False
    """

    family = "button"
    command = Command.BUTTON
    webots_device = False  # Webots' e-puck2 model has no device for it

    @property
    def member_names(self) -> tuple[str, ...]:
        return self.served_names()

    def validate(self, request: Request, values: Sequence[float], now_s: float) -> Verdict:
        return Verdict(out_of_range(self.family, values, 0, 1))

    @property
    def pressed(self) -> bool:
        return bool(self.values[0])
