"""Webots' ``controller.speaker`` module, as Webots ships it (one per class)."""

from ego.controller import Speaker

__all__ = ['Speaker']
