"""Webots' ``controller.light_sensor`` module, as Webots ships it (one per class)."""

from ego.controller import LightSensor

__all__ = ['LightSensor']
