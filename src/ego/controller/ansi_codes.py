"""Webots' ``controller.ansi_codes`` module, as Webots ships it (one per class)."""

from ego.controller.terminal_colours import AnsiCodes

__all__ = ["AnsiCodes"]
