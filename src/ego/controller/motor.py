"""Webots' ``controller.motor`` module, as Webots ships it (one per class)."""

from ego.controller import Motor

__all__ = ['Motor']
