"""Webots' ``controller.display`` module, as Webots ships it (one per class)."""

from ego.controller import Display

__all__ = ['Display']
