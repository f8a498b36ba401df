"""Webots' ``controller.sensor`` module, as Webots ships it (one per class)."""

from ego.controller import Sensor

__all__ = ['Sensor']
