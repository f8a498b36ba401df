"""Webots' ``controller.inertial_unit`` module, as Webots ships it (one per class)."""

from ego.controller import InertialUnit

__all__ = ['InertialUnit']
