"""Webots' ``controller.mouse`` module, as Webots ships it (one per class)."""

from ego.controller import Mouse

__all__ = ['Mouse']
