"""What the floor under the e-puck looks like to its ground sensors and its camera.

A floor gives a reflectance (1.0 white, 0.15 black) at any point; the ground sensors read
it under their three spots and the camera renders it. Two kinds: the default marks (a
black stripe and a disc on white), and a line track (a black line of some width along a
polyline) for line followers.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

__all__ = ["BLACK", "WHITE", "LineTrack", "Marks"]

WHITE = 1.0
BLACK = 0.15


@dataclass(frozen=True)
class Marks:
    """White, with a black stripe along y = 0.2 m and a black disc around (-0.3, -0.3)."""

    def reflectance(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        stripe = np.abs(y - 0.2) < 0.02
        disc = (x + 0.3) ** 2 + (y + 0.3) ** 2 < 0.08**2
        return np.where(stripe | disc, BLACK, WHITE)


@dataclass(frozen=True)
class LineTrack:
    """A black line ``width_m`` wide along ``points`` (closed into a loop if ``closed``)."""

    points: tuple[tuple[float, float], ...]
    width_m: float = 0.02
    closed: bool = True

    def __post_init__(self) -> None:
        if len(self.points) < 2:
            raise ValueError("a line track needs at least two points")
        if not 0.001 <= self.width_m <= 0.2:
            raise ValueError(f"line width {self.width_m} m is outside 0.001..0.2 m")

    def segments(self) -> Sequence[tuple[tuple[float, float], tuple[float, float]]]:
        pts = list(self.points)
        ends = pts[1:] + ([pts[0]] if self.closed else [])
        return list(zip(pts, ends, strict=False))

    def distance(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        """Distance (m) from each point to the line's centre, vectorised over points."""
        best = np.full(np.shape(x), np.inf)
        for (ax, ay), (bx, by) in self.segments():
            dx, dy = bx - ax, by - ay
            length2 = dx * dx + dy * dy or 1e-12
            t = np.clip(((x - ax) * dx + (y - ay) * dy) / length2, 0.0, 1.0)
            best = np.minimum(best, np.hypot(x - (ax + t * dx), y - (ay + t * dy)))
        return best

    def reflectance(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        return np.where(self.distance(x, y) <= self.width_m / 2, BLACK, WHITE)
