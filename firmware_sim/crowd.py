"""Several e-pucks in one emulated world (a swarm): each sees the others.

Each robot keeps its own :class:`~firmware_sim.world.World` (its body, its noise, its
dsPIC), all made from the same world file; a :class:`Crowd` joins them, so that each one
finds the others' bodies on its proximity rays and bumps into them. A body's position is
read as its own emulator last advanced it (at most one step old), so that no world ever
waits on another's lock.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from firmware_sim.world import ROBOT_RADIUS_M, Pose, World

__all__ = ["Crowd", "spread_poses"]


class Crowd:
    """The robots sharing one world."""

    def __init__(self, worlds: Sequence[World]) -> None:
        self.worlds = list(worlds)
        for world in self.worlds:
            world.crowd = self

    def others(self, world: World) -> list[tuple[float, float]]:
        return [w.body_position() for w in self.worlds if w is not world]


def spread_poses(count: int, half_size_m: float, taken: Sequence[Pose] = ()) -> list[Pose]:
    """``count`` start poses on a circle around the arena's centre, facing outwards, at
    least two bodies apart, after the ``taken`` ones a world file gave."""
    poses = list(taken)[:count]
    missing = count - len(poses)
    if missing <= 0:
        return poses
    radius = min(half_size_m * 0.6, max(0.12, missing * 3 * ROBOT_RADIUS_M / math.pi))
    for k in range(missing):
        angle = 2 * math.pi * k / missing
        poses.append(Pose(radius * math.cos(angle), radius * math.sin(angle), angle))
    return poses
