"""Webots' ``controller.field`` module, as Webots ships it (one per class)."""

from ego.controller import Field

__all__ = ['Field']
