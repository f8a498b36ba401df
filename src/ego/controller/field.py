"""Webots' scene-tree ``Field``: a supervisor's (ego.controller.supervisor serves the
emulated world's)."""

from __future__ import annotations

from ego.controller.node import no_simulation

__all__ = ["Field"]


class Field:
    """Webots' scene-tree Field: a supervisor's, and there is no scene tree on a robot."""

    def __init__(self, *args: object, **kwargs: object) -> None:
        no_simulation("Field")
