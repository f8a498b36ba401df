"""Webots' ``controller.gyro`` module, as Webots ships it (one per class)."""

from ego.controller import Gyro

__all__ = ['Gyro']
