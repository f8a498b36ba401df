"""The emulated world's layout: poses, the walled arena, boxes, the lamp and the sound
source, and the rays the IR sensors cast against boxes and other robots (firmware_sim.world
moves a robot among them)."""

from __future__ import annotations

import math
from dataclasses import dataclass

__all__ = ["Arena", "Block", "Lamp", "Pose", "SoundSource", "default_blocks", "ray_box", "ray_disc"]


@dataclass(frozen=True, slots=True)
class Pose:
    x_m: float
    y_m: float
    theta_rad: float


@dataclass(frozen=True, slots=True)
class Arena:
    """A walled arena: walls at x = +-half_size_m and y = +-half_y_m (square unless a
    world file gives it two sides, as Webots' RectangleArena's floorSize does)."""

    half_size_m: float = 0.5
    wall_rgb: tuple[int, int, int] = (200, 190, 170)
    half_y_m: float | None = None
    wall_height_m: float = 0.10

    @property
    def half_extents(self) -> tuple[float, float]:
        return self.half_size_m, self.half_size_m if self.half_y_m is None else self.half_y_m


@dataclass(frozen=True, slots=True)
class Block:
    """A box standing on the floor: an obstacle with a colour to follow. Square, 5 cm high
    and axis-aligned unless a world file gives it two sides, a height and a yaw (the
    boxes of a Webots world); ``half_size_m`` is its half extent along its own x."""

    x_m: float
    y_m: float
    half_size_m: float
    rgb: tuple[int, int, int]
    half_y_m: float | None = None
    yaw_rad: float = 0.0
    height_m: float = 0.05
    #: Its DEF name in a world file, if it has one (a Supervisor finds it by it).
    name: str | None = None

    @property
    def half_extents(self) -> tuple[float, float]:
        return self.half_size_m, self.half_size_m if self.half_y_m is None else self.half_y_m

    def to_local(self, x: float, y: float) -> tuple[float, float]:
        """A world point in the box's frame (centred, its sides along the axes)."""
        c, s = math.cos(self.yaw_rad), math.sin(self.yaw_rad)
        dx, dy = x - self.x_m, y - self.y_m
        return c * dx + s * dy, c * dy - s * dx

    def to_world(self, lx: float, ly: float) -> tuple[float, float]:
        c, s = math.cos(self.yaw_rad), math.sin(self.yaw_rad)
        return self.x_m + c * lx - s * ly, self.y_m + s * lx + c * ly


@dataclass(frozen=True, slots=True)
class Lamp:
    x_m: float = 0.3
    y_m: float = 0.3
    height_m: float = 0.15


@dataclass(frozen=True, slots=True)
class SoundSource:
    x_m: float = -0.3
    y_m: float = 0.3
    frequency_hz: float = 1000.0
    amplitude: float = 900.0  # ADC counts at 10 cm


def default_blocks() -> list[Block]:
    return [
        Block(0.25, -0.25, 0.04, (200, 30, 30)),
        Block(-0.25, -0.22, 0.04, (30, 160, 40)),
        Block(-0.3, 0.05, 0.03, (30, 60, 200)),
    ]


def ray_box(ox: float, oy: float, c: float, s: float, blk: Block) -> float | None:
    """Slab test in the box's frame: distance along the ray to the box, or None."""
    lx, ly = blk.to_local(ox, oy)
    bc, bs = math.cos(blk.yaw_rad), math.sin(blk.yaw_rad)
    dx, dy = bc * c + bs * s, bc * s - bs * c
    bx, by = blk.half_extents
    t0, t1 = -math.inf, math.inf
    for o, d, h in ((lx, dx, bx), (ly, dy, by)):
        if abs(d) < 1e-12:
            if not -h <= o <= h:
                return None
            continue
        a, b = (-h - o) / d, (h - o) / d
        t0, t1 = max(t0, min(a, b)), min(t1, max(a, b))
    if t1 < max(t0, 0.0):
        return None
    return max(t0, 0.0)


def ray_disc(
    ox: float, oy: float, c: float, s: float, px: float, py: float, radius: float
) -> float | None:
    """Distance along the ray to a disc (another e-puck's body), or None if it misses."""
    mx, my = ox - px, oy - py
    b = mx * c + my * s
    disc = b * b - (mx * mx + my * my - radius * radius)
    if disc < 0:
        return None
    t = -b - math.sqrt(disc)
    return t if t >= 0 else None
