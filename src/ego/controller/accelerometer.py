"""Webots' ``controller.accelerometer`` module, as Webots ships it (one per class)."""

from ego.controller import Accelerometer

__all__ = ['Accelerometer']
