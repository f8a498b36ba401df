"""Webots' ``controller.pen`` module, as Webots ships it (one per class)."""

from ego.controller import Pen

__all__ = ['Pen']
