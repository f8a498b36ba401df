"""The e-puck's numbers in ROS 2's units, as epuck_ros2's driver computes them (no I/O).

Every constant and formula follows cyberbotics/epuck_ros2@91ff8a1fcc31db716e0add0a02e830dd
910de669 ``epuck_ros2_driver/src/driver.cpp`` (cited by line below), except the wheel
geometry: the driver's parameters default to a 0.02 m radius and 0.05685 m between the
wheels (:75-76); ego uses the e-puck's own, the one its odometry and emulator use
(:mod:`ego.core.odometry`: 0.0205 m, 0.052 m), so that ``cmd_vel`` and ``odom`` agree
with each other and with the robot. Speeds go to the motors in steps/s with the exact
1000 steps a turn (the driver divides by 0.0068, :296-297).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from ego.core.odometry import AXLE_M, WHEEL_RADIUS_M
from ego.devices.motors import rad_s_to_steps
from ego.ros2.epuck_driver import GROUND_TABLE, INFRARED_TABLE, interpolate_table
from ego.serial.profiles import MAX_SPEED_STEPS

__all__ = [
    "GROUND_TABLE",
    "INFRARED_TABLE",
    "SENSOR_ANGLES_RAD",
    "ScanSpec",
    "interpolate_table",
    "rgb_percent",
    "scan_ranges",
    "twist_to_steps",
    "yaw_quaternion",
]

#: driver.cpp:90-100: ps0..ps7's bearing from the robot's x axis, then the ToF's.
SENSOR_ANGLES_RAD: tuple[float, ...] = tuple(
    math.radians(a) for a in (-15, -45, -90, -150, 150, 90, 45, 15, 0)
)
#: driver.cpp:69-74,77: the Range limits as the driver writes them, min below max (ROS
#: tools check it). An unmerged branch of epuck_ros2 (4ac67cf, "Change min distance")
#: raised both minimums to 0.045, above the IR maximum; the driver at 91ff8a1 keeps these.
INFRARED_MAX_RANGE, INFRARED_MIN_RANGE = 0.025, 0.009
TOF_MAX_RANGE, TOF_MIN_RANGE = 1.0, 0.005
GROUND_MIN_RANGE, GROUND_MAX_RANGE = 0.0, 0.016
SENSOR_DIST_FROM_CENTER = 0.035
OUT_OF_RANGE = 0.0
#: driver.cpp:364, :443: field of view of an IR sensor, of the ToF (VL53L0X).
IR_FOV_RAD, TOF_FOV_RAD = math.radians(15), math.radians(25)


class ScanSpec:
    """The LaserScan epuck_ros2 builds from the IR sensors (driver.cpp:390-428): 21 rays
    15 degrees apart from -150 to 150, eight of them the IR sensors, the middle one the
    ToF, the others out of range; each distance measured from the robot's centre."""

    ANGLE_MIN = math.radians(-150)
    ANGLE_MAX = math.radians(150)
    ANGLE_INCREMENT = math.radians(15)
    RANGE_MIN = INFRARED_MIN_RANGE + SENSOR_DIST_FROM_CENTER
    RANGE_MAX = TOF_MAX_RANGE + SENSOR_DIST_FROM_CENTER
    #: For each ray from -150 degrees: the index of its IR sensor, 8 for the ToF, or None.
    RAYS: tuple[int | None, ...] = (3, None, None, None, 2, None, None, 1, None, 0, 8, 7,
                                    None, 6, None, None, 5, None, None, None, 4)  # fmt: skip


def scan_ranges(distances_m: Sequence[float], tof_m: float = OUT_OF_RANGE) -> list[float]:
    """The scan's 21 ranges from the eight IR distances and the ToF's (0: none), as
    driver.cpp:396-428: an IR distance past INFRARED_MAX_RANGE is out of range (0), and
    every sensor ray adds SENSOR_DIST_FROM_CENTER; the rays between stay 0."""
    ir = [OUT_OF_RANGE if d > INFRARED_MAX_RANGE else d for d in distances_m[:8]]
    values = [*ir, tof_m]
    return [
        OUT_OF_RANGE if ray is None else values[ray] + SENSOR_DIST_FROM_CENTER
        for ray in ScanSpec.RAYS
    ]


def twist_to_steps(
    linear_x: float, angular_z: float,
    wheel_radius_m: float = WHEEL_RADIUS_M, wheel_distance_m: float = AXLE_M,
) -> tuple[int, int]:  # fmt: skip
    """Wheel speeds in steps/s for a Twist (``onCmdVelReceived``, driver.cpp:291-297):
    each wheel's rad/s from the unicycle model, clipped to the motors' +-1000 steps/s.
    A NaN or infinite component stops the robot rather than drive it anywhere."""
    if not (math.isfinite(linear_x) and math.isfinite(angular_z)):
        return (0, 0)
    left = (2.0 * linear_x - angular_z * wheel_distance_m) / (2.0 * wheel_radius_m)
    right = (2.0 * linear_x + angular_z * wheel_distance_m) / (2.0 * wheel_radius_m)

    def steps(rad_s: float) -> int:
        return int(max(-MAX_SPEED_STEPS, min(MAX_SPEED_STEPS, rad_s_to_steps(rad_s))))

    return steps(left), steps(right)


def rgb_percent(data: int) -> tuple[int, int, int]:
    """An RGB LED's Int32 as epuck_ros2 splits it (``onRgbLedReceived``, driver.cpp:
    246-250): 0xRRGGBB, each byte as a percentage (byte / 2.55, truncated)."""
    return tuple(int(((data >> shift) & 0xFF) / 2.55) for shift in (16, 8, 0))  # type: ignore[return-value]


def yaw_quaternion(yaw_rad: float) -> tuple[float, float, float, float]:
    """x, y, z, w of a rotation by ``yaw_rad`` about z (``euler2quaternion(0, 0, yaw)``,
    driver.cpp:281-288)."""
    return (0.0, 0.0, math.sin(yaw_rad / 2), math.cos(yaw_rad / 2))
