"""Webots' ``controller.keyboard`` module, as Webots ships it (one per class)."""

from ego.controller import Keyboard

__all__ = ['Keyboard']
