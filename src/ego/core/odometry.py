"""Dead reckoning from the wheel encoders: the pose the e-puck believes it took.

Sans-I/O: fed step counts, it returns poses. The geometry is the e-puck's (and Webots'
E-puck model's): wheels of 20.5 mm radius, 52 mm apart, 1000 steps a turn.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ego.serial.profiles import STEPS_PER_TURN

__all__ = ["AXLE_M", "WHEEL_RADIUS_M", "Odometry", "Pose2D"]

WHEEL_RADIUS_M = 0.0205
AXLE_M = 0.052
_M_PER_STEP = 2 * math.pi * WHEEL_RADIUS_M / STEPS_PER_TURN


@dataclass(frozen=True, slots=True)
class Pose2D:
    x_m: float
    y_m: float
    theta_rad: float


class Odometry:
    """Integrates wheel motion into a pose, starting at ``start`` (the origin by default)."""

    def __init__(self, start: Pose2D | None = None) -> None:
        self.pose = start or Pose2D(0.0, 0.0, 0.0)
        self._last: tuple[int, int] | None = None

    def from_counts(self, left: int, right: int) -> Pose2D:
        """Advance by the change in the encoders' totals since the last call."""
        if self._last is None:
            self._last = (left, right)
            return self.pose
        dl, dr = left - self._last[0], right - self._last[1]
        self._last = (left, right)
        return self.advance(dl * _M_PER_STEP, dr * _M_PER_STEP)

    def from_speeds(self, left: int, right: int, dt_s: float) -> Pose2D:
        """Advance by wheel speeds (steps/s) held for ``dt_s``: when no encoder is read."""
        self._last = None
        return self.advance(left * _M_PER_STEP * dt_s, right * _M_PER_STEP * dt_s)

    def advance(self, left_m: float, right_m: float) -> Pose2D:
        """Advance by the distances each wheel rolled (midpoint integration)."""
        p = self.pose
        turn = (right_m - left_m) / AXLE_M
        forward = (left_m + right_m) / 2
        heading = p.theta_rad + turn / 2
        self.pose = Pose2D(
            p.x_m + forward * math.cos(heading),
            p.y_m + forward * math.sin(heading),
            math.remainder(p.theta_rad + turn, 2 * math.pi),
        )
        return self.pose
