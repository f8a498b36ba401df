"""Webots' ``controller.motion`` module, as Webots ships it (one per class)."""

from ego.controller.absent import Motion

__all__ = ["Motion"]
