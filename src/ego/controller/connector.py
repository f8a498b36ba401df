"""Webots' ``controller.connector`` module, as Webots ships it (one per class)."""

from ego.controller import Connector

__all__ = ['Connector']
