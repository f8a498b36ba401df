"""Webots' ``Compass``: the e-puck has none; on the emulator (``--port sim``), where the
world file gives the robot one, it reads the emulated world's ground truth."""

from __future__ import annotations

import math

from ego.controller.sensor import GroundTruthDevice

__all__ = ["Compass"]


class Compass(GroundTruthDevice):
    """Webots' Compass; the e-puck has none: on the emulator only (``--port sim``), when
    the world file declares one, it reads the emulated world's ground truth."""

    _node_type = "COMPASS"

    def getValues(self) -> list[float]:
        """North (+y) in the robot's frame (x forward, y left, z up), as Webots' Compass
        (a world declared NUE: north +x in the old robot frame, x right, y up, z back);
        NaN while disabled."""
        values = self._values()
        return [math.nan] * 3 if values is None else list(values)
