"""The eight ambient light sensors ls0..ls7 (wire command O)."""

from __future__ import annotations

from ego.devices.base import ArraySensor
from ego.seam.profile import Command

__all__ = ["LightSensors"]


class LightSensors(ArraySensor):
    """Ambient light, 0..4095, **brighter is lower** (docs/protocol.md).

    The stock Overo firmware sends 10 values; the two extra ones belong to the long-range
    IR sensors and are not light sensors, so only ls0..ls7 are kept.

    >>> robot.light.enable(128)                          # doctest: +SKIP
    >>> robot.step(128); brightest = min(robot.light.values)
    """

    family = "light sensors"
    table_family = "light"
    command = Command.LIGHT
