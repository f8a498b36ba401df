"""Webots' ``controller.radar_target`` module, as Webots ships it (one per class)."""

from ego.controller.absent import RadarTarget

__all__ = ["RadarTarget"]
