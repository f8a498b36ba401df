"""One step's readings of a robot, as the ROS 2 bridge publishes them (no I/O).

The bridge fills a :class:`Reading` from the robot after each step; the message
builders (:mod:`ego.servers.ros2_node.build`) read nothing else. Each field is None
where the robot did not read it this step (its firmware has no such device, or no
sample came yet).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import numpy as np
    from numpy.typing import NDArray

__all__ = ["OdometryState", "Reading"]


@dataclass(frozen=True, slots=True)
class OdometryState:
    """The pose dead reckoning gives (odom frame) and the speeds of the last step."""

    x_m: float
    y_m: float
    theta_rad: float
    linear_mps: float
    angular_radps: float


@dataclass(slots=True)
class Reading:
    """What one step read, with the ROS time (ns since the epoch) it is stamped with."""

    stamp_ns: int
    #: Raw IR counts of ps0..ps7.
    proximity: tuple[int, ...] | None = None
    #: Raw counts of ls0..ls7.
    light: tuple[int, ...] | None = None
    #: Raw counts of gs0..gs2.
    floor: tuple[int, ...] | None = None
    #: x, y, z in m/s^2 (ego's accelerometer axes).
    acceleration: tuple[float, float, float] | None = None
    #: x, y, z in rad/s (ego's gyro axes), where the robot has a gyro.
    angular_velocity: tuple[float, float, float] | None = None
    #: The wheels' angles (rad) and speeds (rad/s).
    wheels_rad: tuple[float, float] | None = None
    wheels_radps: tuple[float, float] | None = None
    odometry: OdometryState | None = None
    #: The ToF's distance in metres (an e-puck2's VL53L0X).
    tof_m: float | None = None
    #: The camera's last image, RGB888 (height, width, 3), and its horizontal FOV.
    image: NDArray[np.uint8] | None = None
    fov_rad: float = 0.84
    #: The image as JPEG, when a subscriber wants the compressed topic.
    jpeg: bytes | None = None
