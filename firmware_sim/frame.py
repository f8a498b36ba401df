"""The frame a world file speaks in, and the emulator's own.

The emulator simulates a flat world whose arena is centred on the origin, x and y on the
floor, z up (Webots' ENU). A Webots world file may say otherwise, and a Supervisor's
controller computes in what the file says:

* its ``RectangleArena`` may stand off the origin and turned about the vertical. Webots'
  RectangleArena PROTO is one Solid (``translation``/``rotation`` are its fields) whose
  floor and four walls are placed in that Solid's own frame, the walls just outside
  +-floorSize/2 along its own x and y. So the arena's inside is the arena's own frame,
  and the emulator simulates in it: every pose the file gives is carried into it on load,
  and every pose a Supervisor reads is carried back out (:class:`Frame`);
* it may be declared ``coordinateSystem "NUE"`` (Webots before R2022a: x north, y up,
  z east). Webots R2022a converts such a world on load, and its converter script
  (``scripts/converter/convert_nue_to_enu_rub_to_flu.py``) maps every ``translation``,
  ``location``, ``direction``, ``axis`` vector (x, y, z) to (-z, -x, y), a ``rotation``'s
  axis the same way with the angle kept, and a box's ``size`` (x, y, z) to (z, x, y): the
  old objects' forward (their -z) becomes +x, their up (+y) becomes +z. The map is a
  proper rotation, so a turn of angle a about the old +y is a turn of a about the new +z.
  :func:`to_enu` does the same to the parsed nodes (and, as the converter does not, turns
  a RectangleArena's two-number floorSize with it: its first side was along the old x);
  :class:`Frame` answers a Supervisor in the file's own NUE numbers by the inverse map.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from firmware_sim.wbt_node import Node

__all__ = ["ENU", "NUE", "Frame", "to_enu"]

ENU = "ENU"
NUE = "NUE"

#: Fields holding a position or a direction (3 numbers), as Webots' converter lists them.
_VECTORS = ("translation", "location", "direction", "axis", "anchor")
#: Fields holding an extent (3 positive numbers).
_SIZES = ("size",)
#: Fields holding two sides of a floor: the first was along the old x, now the new y.
_SIDES = ("floorSize", "floorTileSize")


def _nue_to_enu(v: tuple[float, ...]) -> tuple[float, float, float]:
    return (-v[2], -v[0], v[1])


def _enu_to_nue(v: tuple[float, ...]) -> tuple[float, float, float]:
    return (-v[1], v[2], -v[0])


def to_enu(nodes: list[Node]) -> None:
    """Convert parsed NUE nodes to ENU in place, as Webots' R2022a converter does."""
    seen: set[int] = set()
    for top in nodes:
        for node in top.walk():
            if id(node) in seen:
                continue
            seen.add(id(node))
            _convert(node)


def _convert(node: Node) -> None:
    for key in _VECTORS:
        if key in node.fields:
            node.fields[key] = list(_nue_to_enu(node.numbers(key, 3, (0.0, 0.0, 0.0))))
    if "rotation" in node.fields:
        *axis, angle = node.numbers("rotation", 4, (0.0, 1.0, 0.0, 0.0))
        node.fields["rotation"] = [*_nue_to_enu(tuple(axis)), angle]
    for key in _SIZES:
        value = node.fields.get(key)
        if isinstance(value, list) and len(value) == 3:
            x, y, z = node.numbers(key, 3, (0.0, 0.0, 0.0))
            node.fields[key] = [z, x, y]
    if node.type == "RectangleArena":
        for key in _SIDES:
            if key in node.fields:
                a, b = node.numbers(key, 2, (1.0, 1.0))
                node.fields[key] = [b, a]


@dataclass(frozen=True)
class Frame:
    """Where the emulator's frame (the arena's own, ENU) sits in the file's world frame:
    the arena's centre (x, y, m) and turn about the vertical (rad) in ENU, and the
    convention the file speaks (``ENU`` or ``NUE``)."""

    x_m: float = 0.0
    y_m: float = 0.0
    yaw_rad: float = 0.0
    system: str = ENU

    @property
    def vertical(self) -> tuple[float, float, float]:
        """The world's up axis in the file's own numbers."""
        return (0.0, 1.0, 0.0) if self.system == NUE else (0.0, 0.0, 1.0)

    # -- from the file (in ENU once converted) into the emulator's frame, on load --

    def into_arena(self, x_m: float, y_m: float, yaw_rad: float) -> tuple[float, float, float]:
        """An ENU world pose (x, y, yaw) in the arena's frame."""
        c, s = math.cos(self.yaw_rad), math.sin(self.yaw_rad)
        dx, dy = x_m - self.x_m, y_m - self.y_m
        return (c * dx + s * dy, -s * dx + c * dy, yaw_rad - self.yaw_rad)

    def out_of_arena(self, x_m: float, y_m: float, yaw_rad: float) -> tuple[float, float, float]:
        """An arena-frame pose (x, y, yaw) in the ENU world frame."""
        c, s = math.cos(self.yaw_rad), math.sin(self.yaw_rad)
        return (self.x_m + c * x_m - s * y_m, self.y_m + s * x_m + c * y_m, yaw_rad + self.yaw_rad)

    # -- between the emulator's frame and the file's own numbers (a Supervisor's) --

    def to_file(
        self, x_m: float, y_m: float, z_m: float, yaw_rad: float
    ) -> tuple[float, float, float, float]:
        """An emulator pose as the file writes it: its position, and the angle of its
        turn about :attr:`vertical`."""
        x, y, yaw = self.out_of_arena(x_m, y_m, yaw_rad)
        if self.system == NUE:
            return (*_enu_to_nue((x, y, z_m)), yaw)
        return (x, y, z_m, yaw)

    def from_file(
        self, position: tuple[float, float, float], angle_rad: float
    ) -> tuple[float, float, float, float]:
        """A pose the file's way (a Supervisor's setSFVec3f/setSFRotation) as the
        emulator's x, y, z, yaw."""
        x, y, z = _nue_to_enu(position) if self.system == NUE else position
        ax, ay, yaw = self.into_arena(x, y, angle_rad)
        return (ax, ay, z, yaw)

    def velocity_to_file(
        self, vx: float, vy: float, wz: float
    ) -> tuple[float, float, float, float, float, float]:
        """An emulator velocity (vx, vy m/s, turn rate rad/s) as the file's frame has it:
        linear then angular, each a 3-vector."""
        c, s = math.cos(self.yaw_rad), math.sin(self.yaw_rad)
        linear = (c * vx - s * vy, s * vx + c * vy, 0.0)
        if self.system == NUE:
            return (*_enu_to_nue(linear), *_enu_to_nue((0.0, 0.0, wz)))
        return (*linear, 0.0, 0.0, wz)

    def north_in_body(self, yaw_rad: float) -> tuple[float, float, float]:
        """Webots' Compass: north in the robot's own frame, for the emulator heading
        ``yaw_rad``. ENU: north is +y, the body's frame x forward, y left, z up. NUE:
        north is +x (Webots' default northDirection then), the body's frame as the old
        PROTOs had it (x right, y up, z back), the converter's map undone."""
        heading = yaw_rad + self.yaw_rad
        if self.system == NUE:
            # North (+x NUE) is -y in the converted world; in the body (FLU) that is
            # (-sin h, -cos h, 0), and FLU (f, l, u) is RUB (-l, u, -f).
            return (math.cos(heading), 0.0, math.sin(heading))
        return (math.sin(heading), math.cos(heading), 0.0)
