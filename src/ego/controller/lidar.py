"""Webots' ``controller.lidar`` module, as Webots ships it (one per class)."""

from ego.controller import Lidar

__all__ = ['Lidar']
