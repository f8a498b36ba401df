"""Webots' ``controller.compass`` module, as Webots ships it (one per class)."""

from ego.controller import Compass

__all__ = ['Compass']
