"""Webots' ``controller.touch_sensor`` module, as Webots ships it (one per class)."""

from ego.controller import TouchSensor

__all__ = ['TouchSensor']
