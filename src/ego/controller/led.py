"""Webots' ``controller.led`` module, as Webots ships it (one per class)."""

from ego.controller import LED

__all__ = ['LED']
