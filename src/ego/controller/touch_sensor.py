"""Webots' ``TouchSensor``: the e-puck has none; on the emulator (``--port sim``), where the
world file gives the robot one, it reads the emulated world's ground truth."""

from __future__ import annotations

import math

from ego.controller.sensor import GroundTruthDevice

__all__ = ["TouchSensor"]


class TouchSensor(GroundTruthDevice):
    """Webots' TouchSensor; the e-puck has none: on the emulator only (``--port sim``), when
    the world file declares one, it reads the emulated world's ground truth."""

    _node_type = "TOUCH_SENSOR"

    def getValue(self) -> float:
        """1.0 when the body touches a wall or a box (NaN while disabled)."""
        if not self._period:
            return math.nan
        world = self._truth().true_world
        return 1.0 if world is not None and world.touching() else 0.0

    value = property(lambda self: self.getValue())
