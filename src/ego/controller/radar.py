"""Webots' ``Radar``: the e-puck has none: ``getDevice`` never gives
one (Webots' warning and None); the class exists so that a controller importing it runs."""

from ego.controller.device import Device

__all__ = ["Radar"]


class Radar(Device):
    """Webots' Radar; the e-puck has none."""

    _node_type = "RADAR"
