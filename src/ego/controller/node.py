"""Webots' ``controller.node`` module, as Webots ships it (one per class)."""

from ego.controller import Node

__all__ = ['Node']
