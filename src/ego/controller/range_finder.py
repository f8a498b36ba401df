"""Webots' ``controller.range_finder`` module, as Webots ships it (one per class)."""

from ego.controller import RangeFinder

__all__ = ['RangeFinder']
