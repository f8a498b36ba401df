"""Webots' ``controller.device`` module, as Webots ships it (one per class)."""

from ego.controller import Device

__all__ = ['Device']
