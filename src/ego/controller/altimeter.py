"""Webots' ``controller.altimeter`` module, as Webots ships it (one per class)."""

from ego.controller import Altimeter

__all__ = ['Altimeter']
