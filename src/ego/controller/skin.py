"""Webots' ``controller.skin`` module, as Webots ships it (one per class)."""

from ego.controller import Skin

__all__ = ['Skin']
