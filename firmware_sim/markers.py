"""Named solids of a world that nothing bumps into or senses: a flat marker on the floor,
a Plane, a goal's Transform-like Solid with no box. A Webots Supervisor finds them by
their DEF name (``getFromDef``), reads and moves them; the emulator models only their
pose, as their shapes give it nothing to model (no bounding box a sensor's ray meets)."""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["Marker"]


@dataclass(frozen=True)
class Marker:
    """A named solid's pose: x, y, z (m) and its yaw about the vertical (rad), and the
    Webots node type it was written as (``Solid``, ``Transform``...)."""

    name: str
    x_m: float
    y_m: float
    z_m: float = 0.0
    yaw_rad: float = 0.0
    kind: str = "Solid"
