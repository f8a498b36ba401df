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
        """North (+y) in the robot's frame (x forward, y left, z up), as Webots' Compass;
        NaN while disabled."""
        pose = self._pose()
        if pose is None:
            return [math.nan] * 3
        return [math.sin(pose.theta_rad), math.cos(pose.theta_rad), 0.0]
