"""Webots' ``Mouse``: a robot has no 3D view to click in, so nothing ever happens."""

from __future__ import annotations

import math

__all__ = ["Mouse", "MouseState", "Polled"]


class MouseState:
    """What Webots' Mouse reports; no window on a robot: no button, no position."""

    def __init__(self) -> None:
        self.left = self.middle = self.right = False
        self.u = self.v = self.x = self.y = self.z = math.nan


class Polled:
    """An input device enabled at a sampling period, which Webots polls each step."""

    def __init__(self, sampling_period: int | None = None) -> None:
        self._period = int(sampling_period or 0)

    def enable(self, samplingPeriod: int) -> None:
        self._period = int(samplingPeriod)

    def disable(self) -> None:
        self._period = 0

    def getSamplingPeriod(self) -> int:
        return self._period


class Mouse(Polled):
    """Webots' Mouse: a robot has no 3D view to click in, so nothing ever happens."""

    def __init__(self, sampling_period: int | None = None) -> None:
        super().__init__(sampling_period)
        self._3d = False

    def enable3dPosition(self) -> None:
        self._3d = True

    def disable3dPosition(self) -> None:
        self._3d = False

    def is3dPositionEnabled(self) -> bool:
        return self._3d

    def getState(self) -> MouseState:
        return MouseState()
