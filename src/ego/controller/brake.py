"""Webots' ``Brake``: the e-puck's wheels have none: ``getDevice`` never gives
one (Webots' warning and None); the class exists so that a controller importing it runs."""

from ego.controller.device import Device

__all__ = ["Brake"]


class Brake(Device):
    """Webots' Brake; the e-puck's wheels have none."""

    _node_type = "BRAKE"
