"""Webots' ``controller.brake`` module, as Webots ships it (one per class)."""

from ego.controller import Brake

__all__ = ['Brake']
