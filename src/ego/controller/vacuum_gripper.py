"""Webots' ``controller.vacuum_gripper`` module, as Webots ships it (one per class)."""

from ego.controller import VacuumGripper

__all__ = ['VacuumGripper']
