"""Webots' ``controller.emitter`` module, as Webots ships it (one per class)."""

from ego.controller import Emitter

__all__ = ['Emitter']
