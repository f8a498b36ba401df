"""Webots' ``controller.supervisor`` module, as Webots ships it (one per class)."""

from ego.controller import Supervisor

__all__ = ['Supervisor']
