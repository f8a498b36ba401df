"""Webots' ``controller.lidar_point`` module, as Webots ships it (one per class)."""

from ego.controller.absent import LidarPoint

__all__ = ["LidarPoint"]
