"""Webots' ``controller.receiver`` module, as Webots ships it (one per class)."""

from ego.controller import Receiver

__all__ = ['Receiver']
