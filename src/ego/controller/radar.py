"""Webots' ``controller.radar`` module, as Webots ships it (one per class)."""

from ego.controller import Radar

__all__ = ['Radar']
