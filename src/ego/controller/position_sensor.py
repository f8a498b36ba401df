"""Webots' ``controller.position_sensor`` module, as Webots ships it (one per class)."""

from ego.controller import PositionSensor

__all__ = ['PositionSensor']
