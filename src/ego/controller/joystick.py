"""Webots' ``Joystick``: none is connected to a robot's controller."""

from __future__ import annotations

from ego.controller.mouse import Polled

__all__ = ["Joystick"]


class Joystick(Polled):
    """Webots' Joystick: none is connected to a robot's controller."""

    def isConnected(self) -> bool:
        return False

    def getModel(self) -> str:
        return ""

    def getNumberOfAxes(self) -> int:
        return 0

    def getAxisValue(self, axis: int) -> int:
        return 0

    def getNumberOfPovs(self) -> int:
        return 0

    def getPovValue(self, pov: int) -> int:
        return 0

    def getPressedButton(self) -> int:
        return -1
