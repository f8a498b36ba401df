"""Webots' ``controller.gps`` module, as Webots ships it (one per class)."""

from ego.controller import GPS

__all__ = ['GPS']
