"""The eight ambient light sensors ls0..ls7 (wire command O)."""

from __future__ import annotations

from ego.devices.base import ArraySensor
from ego.devices.table import RAW, TABLE, Series
from ego.seam.profile import Command

__all__ = ["LightSensors"]


@TABLE.declare(
    "light",
    webots_rank=6,
    series=Series("light", f"{RAW}, lower is brighter", tuple(f"ls{i}" for i in range(8))),
)
class LightSensors(ArraySensor):
    """Ambient light, 0..4095, **brighter is lower** (docs/protocol.md).

    The stock Overo firmware sends 10 values; the two extra ones belong to the long-range
    IR sensors and are not light sensors, so only ls0..ls7 are kept.

    >>> robot.light.enable(128)                          # doctest: +SKIP
    >>> robot.step(128); brightest = min(robot.light.values)
    """

    family = "light sensors"
    command = Command.LIGHT
