"""epuck_ros2's conversions of raw e-puck readings, written once for every ROS 2 output of
ego (the bridge, :mod:`ego.servers.ros2_node`, and the ROS 2 recordings,
:mod:`ego.recording.ros2_topics`): its distance tables and its ``interpolateTable``
(cyberbotics/epuck_ros2@91ff8a1 ``epuck_ros2_driver/src/driver.cpp``)."""

from __future__ import annotations

import itertools
from collections.abc import Sequence

__all__ = ["GROUND_TABLE", "INFRARED_TABLE", "interpolate_table"]

#: driver.cpp:87-88: (distance m, raw IR), raw falling as the distance grows.
INFRARED_TABLE: tuple[tuple[float, float], ...] = (
    (0.0, 4095.0), (0.005, 2133.33), (0.01, 1465.73), (0.015, 601.46),
    (0.02, 383.84), (0.03, 234.93), (0.04, 158.03), (0.05, 120.0),
)  # fmt: skip
#: driver.cpp:89: the ground sensors' (distance m, raw).
GROUND_TABLE: tuple[tuple[float, float], ...] = ((0.0, 1000.0), (0.016, 300.0))


def _line(value: float, x0: float, y0: float, x1: float, y1: float) -> float:
    return (y1 - y0) / (x1 - x0) * (value - x0) + y0


def interpolate_table(value: float, table: Sequence[tuple[float, float]]) -> float:
    """``interpolateTable`` (driver.cpp:333-350): the distance for raw ``value``, linear
    between the two rows around it, extrapolated from the end rows outside them."""
    for (d0, r0), (d1, r1) in itertools.pairwise(table):
        if r1 <= value < r0 or r0 < value <= r1:
            return _line(value, r0, d0, r1, d1)
    if value > table[0][1]:
        (d0, r0), (d1, r1) = table[0], table[1]
    else:
        (d0, r0), (d1, r1) = table[-2], table[-1]
    return _line(value, r0, d0, r1, d1)
