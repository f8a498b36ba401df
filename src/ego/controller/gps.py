"""Webots' ``GPS``: the e-puck has none; on the emulator (``--port sim``), where the
world file gives the robot one, it reads the emulated world's ground truth."""

from __future__ import annotations

import math

from ego.controller.sensor import GroundTruthDevice

__all__ = ["GPS"]


class GPS(GroundTruthDevice):
    """Webots' GPS; the e-puck has none: on the emulator only (``--port sim``), when
    the world file declares one, it reads the emulated world's ground truth."""

    _node_type = "GPS"

    def getValues(self) -> list[float]:
        """x, y, z (m) of the device in the world's frame (Webots' ENU: x east, y north,
        z up; a world declared NUE: its own x north, y up, z east): the robot's centre,
        or where the world mounts it (an E-puck slot); NaN while disabled."""
        values = self._values()
        return [math.nan] * 3 if values is None else list(values)
