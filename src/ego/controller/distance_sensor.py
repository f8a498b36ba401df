"""Webots' ``controller.distance_sensor`` module, as Webots ships it (one per class)."""

from ego.controller import DistanceSensor

__all__ = ['DistanceSensor']
