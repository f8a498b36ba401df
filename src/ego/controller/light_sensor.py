"""Webots' ``LightSensor``: ls0..ls7."""

from __future__ import annotations

from ego.controller.device import view
from ego.controller.sensor import _ValueSensor

__all__ = ["LightSensor"]

LIGHT_TABLE = (1, 4095, 0.01, 2, 0, 0.01)


@view("LightSensor")
class LightSensor(_ValueSensor):
    """ls0..ls7: 0..4095, lower is brighter (the e-puck's own convention)."""

    _table = LIGHT_TABLE
