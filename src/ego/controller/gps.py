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
        """x, y, z (m) of the robot's centre in Webots' ENU frame (x east, y north, z up);
        NaN while disabled."""
        pose = self._pose()
        return [math.nan] * 3 if pose is None else [pose.x_m, pose.y_m, 0.0]
