"""The solids of a Webots world file the emulator models: boxes (standing, turned about
the vertical or lying on a face) and named solids of any other shape (markers), read
from :mod:`firmware_sim.wbt`'s nodes."""

from __future__ import annotations

import math

from firmware_sim.markers import Marker
from firmware_sim.wbt_node import Node
from firmware_sim.world import Block

__all__ = ["MARKER_TYPES", "block", "box_shape", "marker", "named", "yaw"]

#: Node types whose DEF-named instances a Supervisor finds (``getFromDef``) whatever
#: their shape: a flat marker, a Plane, a goal with no box.
MARKER_TYPES = frozenset({"Solid", "Transform", "Pose", "Group"})


def yaw(rotation: tuple[float, ...], what: str) -> float:
    """The angle about +z of a Webots axis-angle rotation; refused if it tilts."""
    ax, ay, az, angle = rotation
    if abs(math.sin(angle)) < 1e-6 and math.cos(angle) > 0:
        return 0.0
    norm = math.sqrt(ax * ax + ay * ay + az * az)
    if norm == 0 or math.hypot(ax, ay) / norm > 1e-3:
        raise ValueError(f"{what} is rotated about {rotation[:3]}, not the vertical: "
                         "the emulator's world is flat")  # fmt: skip
    return angle * math.copysign(1.0, az)


def box_shape(solid: Node) -> tuple[tuple[float, ...], tuple[int, int, int]] | None:
    children = solid.fields.get("children") or []
    for child in children if isinstance(children, list) else [children]:
        if not isinstance(child, Node) or child.type != "Shape":
            continue
        geometry = child.fields.get("geometry")
        if isinstance(geometry, Node) and geometry.type == "Box":
            return geometry.numbers("size", 3, (2.0, 2.0, 2.0)), _colour(child)
    return None


def _colour(shape: Node) -> tuple[int, int, int]:
    appearance = shape.fields.get("appearance")
    for sub in appearance.walk() if isinstance(appearance, Node) else ():
        for key in ("baseColor", "diffuseColor"):
            if key in sub.fields:
                r, g, b = sub.numbers(key, 3, (1.0, 1.0, 1.0), 0.0, 1.0)
                return (round(255 * r), round(255 * g), round(255 * b))
    return (200, 200, 200)


def block(node: Node, size: tuple[float, ...], rgb: tuple[int, int, int]) -> Block:
    x, y, _ = node.numbers("translation", 3, (0.0, 0.0, 0.0))
    if min(size) <= 0:
        raise ValueError(f"{node.type} size must be positive, not {size}")
    rotation = node.numbers("rotation", 4, (0.0, 0.0, 1.0, 0.0))
    (sx, sy, sz), turn = _standing(rotation, size, named(node))
    return Block(x, y, sx / 2, rgb, half_y_m=sy / 2, yaw_rad=turn, height_m=sz, name=node.name)


def _matrix(rotation: tuple[float, ...]) -> list[list[float]]:
    """The 3x3 matrix of a Webots axis-angle rotation (Rodrigues' formula)."""
    ax, ay, az, angle = rotation
    norm = math.sqrt(ax * ax + ay * ay + az * az)
    if norm == 0:
        return [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
    x, y, z = ax / norm, ay / norm, az / norm
    c, s = math.cos(angle), math.sin(angle)
    t = 1 - c
    return [
        [t * x * x + c, t * x * y - z * s, t * x * z + y * s],
        [t * x * y + z * s, t * y * y + c, t * y * z - x * s],
        [t * x * z - y * s, t * y * z + x * s, t * z * z + c],
    ]


def _standing(
    rotation: tuple[float, ...], size: tuple[float, ...], what: str
) -> tuple[tuple[float, float, float], float]:
    """A box's footprint (x, y along its yaw), height and yaw, for any rotation that
    leaves one of its faces on the floor: about the vertical, or one that lies it on a
    face (Webots' world converter writes ``rotation 1 0 0 1.5708`` for a box whose
    height was its y). A tilt that stands it on an edge or a corner is refused."""
    m = _matrix(rotation)
    # The box's own axis that the rotation turns vertical: its column's z is +-1.
    upright = [k for k in range(3) if abs(abs(m[2][k]) - 1.0) < 1e-3]
    if not upright:
        turn = " ".join(f"{v:g}" for v in rotation)
        raise ValueError(f"{what}.rotation {turn} stands the box on an edge or a corner: "
                         "the emulator's world is flat (a box may turn about the vertical, "
                         "or lie on a face)")  # fmt: skip
    k = upright[0]
    across = [j for j in range(3) if j != k]
    first = across[0]  # the footprint's x: this axis, turned into the floor's plane
    yaw = math.atan2(m[1][first], m[0][first])
    return (size[first], size[across[1]], size[k]), yaw


def named(node: Node) -> str:
    """The node as an error names it: its type, and its DEF name if it has one."""
    return f"{node.type} {node.name}" if node.name else node.type


def marker(node: Node) -> Marker:
    """A named solid with no box: its pose, for a Supervisor's ``getFromDef``."""
    x, y, z = node.numbers("translation", 3, (0.0, 0.0, 0.0))
    rotation = node.numbers("rotation", 4, (0.0, 0.0, 1.0, 0.0))
    turn = yaw(rotation, f"{named(node)}.rotation")
    return Marker(str(node.name), x, y, z, turn, node.type)
