"""Webots' ``controller.joystick`` module, as Webots ships it (one per class)."""

from ego.controller import Joystick

__all__ = ['Joystick']
