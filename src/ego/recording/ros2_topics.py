"""epuck_ros2's topics, derived from the device table: what a ROS 2 recording holds.

Each tagged row of :data:`ego.devices.table.TABLE` yields its topic by its Webots node
type, so a family the table gains appears here with no edit (the e-puck2's ``tof`` row,
a ``DistanceSensor`` in mm, becomes ``/tof``):

==================  ==========================================  =========================
row kind            topic                                       message
==================  ==========================================  =========================
DistanceSensor      ``/<name>`` (ps0..ps7, gs0..gs2, tof)       sensor_msgs/msg/Range
LightSensor         ``/<name>`` (ls0..ls7)                      sensor_msgs/msg/Illuminance
Accelerometer/Gyro  ``/imu`` (one for both)                     sensor_msgs/msg/Imu
PositionSensor      ``/joint_states`` (one for all)             sensor_msgs/msg/JointState
Motor               ``/cmd_vel``: the wheel speeds asked         geometry_msgs/msg/Twist
Camera              ``/image_raw``, ``/image_raw/compressed``,   Image, CompressedImage,
                    ``/camera_info``                            CameraInfo
==================  ==========================================  =========================

and always ``/odom`` and ``/tf`` (ego's odometry) and, with the proximity sensors,
``/scan``; ``/tf_static`` places the sensors' frames once (:func:`static_transforms`).
A row of another kind (LEDs, microphones) has no epuck_ros2 topic.

The conversions follow epuck_ros2's driver as read at
``cyberbotics/epuck_ros2@91ff8a1fcc31db716e0add0a02e830dd910de669:epuck_ros2_driver/src/driver.cpp``:
``INFRARED_TABLE``/``GROUND_TABLE`` and ``interpolateTable`` (raw counts to metres), the
Range limits and fields of view (IR ``min_range`` 0.009 below ``max_range`` 0.025, ToF
0.005..1.0: an unmerged branch, 4ac67cf, had 0.045 above the IR maximum, which ROS tools
refuse), ``publishDistanceData`` for ``/scan`` (21 rays, -150°
to 150° by 15°, each IR distance over 0.025 m out of range, 0.035 m added), the raw light
count as the illuminance, and the frames ``odom`` → ``base_link``. A topic whose family
has no reading in a step (off, or not served) is not written that step: nothing made up.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from ego.core.odometry import AXLE_M, WHEEL_RADIUS_M
from ego.devices.table import TABLE, DeviceSpec, DeviceTable
from ego.ros2.epuck_driver import GROUND_TABLE, INFRARED_TABLE, interpolate_table
from ego.serial.profiles import STEPS_PER_TURN

__all__ = [
    "GROUND_TABLE",
    "INFRARED_TABLE",
    "RangeModel",
    "Ros2Topic",
    "StepData",
    "interpolate_table",
    "ros2_topics",
    "static_transforms",
]

_SENSOR_FROM_CENTER_M = 0.035  # driver.cpp SENSOR_DIST_FROM_CENTER
_IR_CUT_M = 0.025  # driver.cpp INFRARED_MAX_RANGE: farther is OUT_OF_RANGE in the scan
_M_PER_STEP = 2 * math.pi * WHEEL_RADIUS_M / STEPS_PER_TURN
_RAD_PER_STEP = 2 * math.pi / STEPS_PER_TURN


@dataclass(frozen=True, slots=True)
class RangeModel:
    """How a DistanceSensor's reading becomes a Range: metres, limits, field of view."""

    to_m: Callable[[float], float]
    min_range: float
    max_range: float
    fov_deg: float


#: By family (raw counts need the family's table), then by the row's units.
_RANGE_BY_FAMILY = {
    "proximity": RangeModel(lambda v: interpolate_table(v, INFRARED_TABLE), 0.009, 0.025, 15),
    "floor": RangeModel(lambda v: interpolate_table(v, GROUND_TABLE), 0.0, 0.016, 15),
}
_RANGE_BY_UNITS = {
    "mm": RangeModel(lambda v: v / 1000.0, 0.005, 1.0, 25),  # driver.cpp TOF_*, 25° fov
    "m": RangeModel(lambda v: v, 0.0, math.inf, 25),
}
#: Angular rate units a Gyro row may have, to rad/s (a raw gyro has no known scale).
_GYRO_SCALE = {"rad/s": 1.0, "deg/s": math.pi / 180, "°/s": math.pi / 180}


@dataclass(frozen=True, slots=True)
class StepData:
    """One step as the topics read it: the telemetry sample, its time, the message maker."""

    sample: dict[str, Any]
    time_ns: int
    make: Callable[..., Any]  # make("pkg/msg/Name", **fields) -> message

    def reading(self, row: DeviceSpec) -> float | None:
        values = self.sample.get(row.family)
        if not isinstance(values, list) or row.index >= len(values):
            return None
        return float(values[row.index])

    def header(self, frame_id: str) -> Any:
        sec, nanosec = divmod(self.time_ns, 1_000_000_000)
        stamp = self.make("builtin_interfaces/msg/Time", sec=sec, nanosec=nanosec)
        return self.make("std_msgs/msg/Header", stamp=stamp, frame_id=frame_id)


@dataclass(frozen=True, slots=True)
class Ros2Topic:
    """One topic: its name, its message type and how a step becomes its message (None:
    nothing this step)."""

    topic: str
    type_name: str
    build: Callable[[StepData], Any | None]


def _range_model(row: DeviceSpec) -> RangeModel | None:
    return _RANGE_BY_FAMILY.get(row.family) or _RANGE_BY_UNITS.get(row.units)


def _range_topic(row: DeviceSpec, model: RangeModel) -> Ros2Topic:
    def build(step: StepData) -> Any | None:
        raw = step.reading(row)
        if raw is None:
            return None
        return step.make(
            "sensor_msgs/msg/Range", header=step.header(row.name), radiation_type=1,
            field_of_view=math.radians(model.fov_deg), min_range=model.min_range,
            max_range=model.max_range, range=model.to_m(raw), variance=0.0,
        )  # fmt: skip

    return Ros2Topic(f"/{row.name}", "sensor_msgs/msg/Range", build)


def _light_topic(row: DeviceSpec) -> Ros2Topic:
    def build(step: StepData) -> Any | None:
        raw = step.reading(row)
        if raw is None:
            return None
        return step.make("sensor_msgs/msg/Illuminance", header=step.header(row.name),
                         illuminance=raw, variance=0.0)  # fmt: skip

    return Ros2Topic(f"/{row.name}", "sensor_msgs/msg/Illuminance", build)


def _imu_topic(rows: list[DeviceSpec]) -> Ros2Topic:
    import numpy as np

    accel = next((r for r in rows if r.kind == "Accelerometer"), None)
    gyro = next((r for r in rows if r.kind == "Gyro" and r.units in _GYRO_SCALE), None)

    def vector(step: StepData, row: DeviceSpec | None, scale: float) -> list[float] | None:
        values = step.sample.get(row.family) if row is not None else None
        if not isinstance(values, list) or len(values) < 3:
            return None
        return [float(v) * scale for v in values[:3]]

    def build(step: StepData) -> Any | None:
        a = vector(step, accel, 1.0)
        w = vector(step, gyro, _GYRO_SCALE[gyro.units] if gyro else 1.0)
        if a is None and w is None:
            return None
        unknown = np.array([-1.0, *[0.0] * 8])  # REP-145: element 0 at -1, no estimate
        known = np.zeros(9)
        v3 = "geometry_msgs/msg/Vector3"
        return step.make(
            "sensor_msgs/msg/Imu", header=step.header("base_link"),
            orientation=step.make("geometry_msgs/msg/Quaternion", x=0.0, y=0.0, z=0.0, w=1.0),
            orientation_covariance=unknown,
            angular_velocity=step.make(v3, **dict(zip("xyz", w or [0.0] * 3, strict=True))),
            angular_velocity_covariance=known if w else unknown,
            linear_acceleration=step.make(v3, **dict(zip("xyz", a or [0.0] * 3, strict=True))),
            linear_acceleration_covariance=known if a else unknown,
        )  # fmt: skip

    return Ros2Topic("/imu", "sensor_msgs/msg/Imu", build)


def _joint_topic(rows: list[DeviceSpec], table: DeviceTable) -> Ros2Topic:
    import numpy as np

    def per(row: DeviceSpec) -> float:
        series = table.family(row.family).series
        return series.webots[1] if series is not None and series.webots else 1.0

    def build(step: StepData) -> Any | None:
        found = [(r, step.reading(r)) for r in rows]
        read = [(r, v * per(r)) for r, v in found if v is not None]
        if not read:
            return None
        return step.make("sensor_msgs/msg/JointState", header=step.header("base_link"),
                         name=[r.name for r, _ in read],
                         position=np.array([v for _, v in read], dtype=np.float64),
                         velocity=np.zeros(0), effort=np.zeros(0))  # fmt: skip

    return Ros2Topic("/joint_states", "sensor_msgs/msg/JointState", build)


def _twist(step: StepData, left: float, right: float) -> Any:
    """Wheel speeds (steps/s) as a body twist: m/s forward, rad/s about z."""
    v3 = "geometry_msgs/msg/Vector3"
    linear = (left + right) / 2 * _M_PER_STEP
    angular = (right - left) * _M_PER_STEP / AXLE_M
    return step.make("geometry_msgs/msg/Twist", linear=step.make(v3, x=linear, y=0.0, z=0.0),
                     angular=step.make(v3, x=0.0, y=0.0, z=angular))  # fmt: skip


def _cmd_vel(step: StepData) -> Any | None:
    speed = step.sample.get("speed")
    return _twist(step, *speed) if isinstance(speed, list) and len(speed) == 2 else None


def _pose(step: StepData) -> tuple[Any, Any] | None:
    """The odometry pose as a position and a quaternion (yaw only)."""
    pose = step.sample.get("odometry")
    if not isinstance(pose, list) or len(pose) != 3:
        return None
    x, y, theta = pose
    point = step.make("geometry_msgs/msg/Point", x=float(x), y=float(y), z=0.0)
    turn = step.make("geometry_msgs/msg/Quaternion", x=0.0, y=0.0, z=math.sin(theta / 2),
                     w=math.cos(theta / 2))  # fmt: skip
    return point, turn


def _odom(step: StepData) -> Any | None:
    import numpy as np

    pose = _pose(step)
    if pose is None:
        return None
    twist = _cmd_vel(step) or _twist(step, 0, 0)
    zeros = np.zeros(36)
    return step.make(
        "nav_msgs/msg/Odometry", header=step.header("odom"), child_frame_id="base_link",
        pose=step.make("geometry_msgs/msg/PoseWithCovariance",
                       pose=step.make("geometry_msgs/msg/Pose", position=pose[0],
                                      orientation=pose[1]), covariance=zeros),
        twist=step.make("geometry_msgs/msg/TwistWithCovariance", twist=twist, covariance=zeros),
    )  # fmt: skip


def _tf(step: StepData) -> Any | None:
    pose = _pose(step)
    if pose is None:
        return None
    point, turn = pose
    shift = step.make("geometry_msgs/msg/Vector3", x=point.x, y=point.y, z=0.0)
    transform = step.make("geometry_msgs/msg/Transform", translation=shift, rotation=turn)
    moved = step.make("geometry_msgs/msg/TransformStamped", header=step.header("odom"),
                      child_frame_id="base_link", transform=transform)  # fmt: skip
    return step.make("tf2_msgs/msg/TFMessage", transforms=[moved])


#: driver.cpp publishDistanceData: which sensor each of the 21 rays (-150°..150°) reads.
_SCAN_RAYS = ("ps3", None, None, None, "ps2", None, None, "ps1", None, "ps0", "tof",
              "ps7", None, "ps6", None, None, "ps5", None, None, None, "ps4")  # fmt: skip


def _scan_topic(table: DeviceTable) -> Ros2Topic:
    import numpy as np

    rows = {name: table.find(name) for name in _SCAN_RAYS if name is not None}

    def ray(step: StepData, name: str | None) -> float:
        row = rows.get(name) if name else None
        raw = step.reading(row) if row is not None else None
        model = _range_model(row) if row is not None else None
        if raw is None or model is None:
            return 0.0 if name is None else _SENSOR_FROM_CENTER_M  # OUT_OF_RANGE (+0.035)
        metres = model.to_m(raw)
        if row is not None and row.family == "proximity" and metres > _IR_CUT_M:
            metres = 0.0
        return metres + _SENSOR_FROM_CENTER_M

    def build(step: StepData) -> Any | None:
        if not isinstance(step.sample.get("proximity"), list):
            return None
        ranges = np.array([ray(step, name) for name in _SCAN_RAYS], dtype=np.float32)
        step_s = float(step.sample.get("step_ms") or 0.0) / 1000.0
        return step.make(
            "sensor_msgs/msg/LaserScan", header=step.header("laser_scanner"),
            angle_min=math.radians(-150), angle_max=math.radians(150),
            angle_increment=math.radians(15), time_increment=0.0, scan_time=step_s,
            range_min=0.009 + _SENSOR_FROM_CENTER_M, range_max=1.0 + _SENSOR_FROM_CENTER_M,
            ranges=ranges, intensities=np.zeros(0, dtype=np.float32),
        )  # fmt: skip

    return Ros2Topic("/scan", "sensor_msgs/msg/LaserScan", build)


#: driver.cpp DISTANCE_SENSOR_ANGLE: each IR sensor's heading (degrees), ps0..ps7.
_IR_DEGREES = (-15, -45, -90, -150, 150, 90, 45, 15)


def _mount(name: str) -> tuple[float, float, float] | None:
    """Where driver.cpp's static broadcasters put a sensor's frame on ``base_link``:
    (x m, y m, yaw rad); None for a device it does not place."""
    prefix, number = name.rstrip("0123456789"), name[len(name.rstrip("0123456789")):]
    index = int(number) if number else -1
    if prefix in ("ps", "ls") and 0 <= index < 8:
        yaw = math.radians(_IR_DEGREES[index])
        return (_SENSOR_FROM_CENTER_M * math.cos(yaw), _SENSOR_FROM_CENTER_M * math.sin(yaw), yaw)
    if prefix == "gs" and 0 <= index < 3:  # as driver.cpp writes it: the ps angles reused
        return (_SENSOR_FROM_CENTER_M - 0.005, 0.009 - index * 0.009,
                math.radians(_IR_DEGREES[index]))  # fmt: skip
    if name == "tof":
        return (_SENSOR_FROM_CENTER_M, 0.0, 0.0)
    return None


def static_transforms(table: DeviceTable = TABLE) -> Ros2Topic:
    """``/tf_static``: ``base_link`` to ``laser_scanner`` and to each sensor's frame the
    table has and driver.cpp places (its StaticTransformBroadcasters), once."""
    mounts = {"laser_scanner": (0.0, 0.0, 0.0)}
    for row in table.devices:
        found = _mount(row.name) if row.kind in ("DistanceSensor", "LightSensor") else None
        if found is not None:
            mounts[row.name] = found

    def build(step: StepData) -> Any:
        transforms = []
        for frame, (x, y, heading) in mounts.items():
            shift = step.make("geometry_msgs/msg/Vector3", x=x, y=y, z=0.0)
            turn = step.make("geometry_msgs/msg/Quaternion", x=0.0, y=0.0,
                             z=math.sin(heading / 2), w=math.cos(heading / 2))  # fmt: skip
            transform = step.make("geometry_msgs/msg/Transform", translation=shift, rotation=turn)
            transforms.append(step.make("geometry_msgs/msg/TransformStamped",
                                        header=step.header("base_link"), child_frame_id=frame,
                                        transform=transform))  # fmt: skip
        return step.make("tf2_msgs/msg/TFMessage", transforms=transforms)

    return Ros2Topic("/tf_static", "tf2_msgs/msg/TFMessage", build)


def ros2_topics(table: DeviceTable = TABLE) -> tuple[Ros2Topic, ...]:
    """The topics of a robot with ``table``'s devices (the camera's are written from its
    frames, not from a sample: :mod:`ego.recording.ros2_bag`)."""
    topics: list[Ros2Topic] = []
    by_kind: dict[str, list[DeviceSpec]] = {}
    for row in table.devices:
        by_kind.setdefault(row.kind, []).append(row)
        model = _range_model(row) if row.kind == "DistanceSensor" else None
        if model is not None:
            topics.append(_range_topic(row, model))
        elif row.kind == "LightSensor":
            topics.append(_light_topic(row))
    if "Accelerometer" in by_kind or "Gyro" in by_kind:
        topics.append(_imu_topic([*by_kind.get("Accelerometer", []), *by_kind.get("Gyro", [])]))
    if "PositionSensor" in by_kind:
        topics.append(_joint_topic(by_kind["PositionSensor"], table))
    if "Motor" in by_kind:
        topics.append(Ros2Topic("/cmd_vel", "geometry_msgs/msg/Twist", _cmd_vel))
    topics += [Ros2Topic("/odom", "nav_msgs/msg/Odometry", _odom),
               Ros2Topic("/tf", "tf2_msgs/msg/TFMessage", _tf)]  # fmt: skip
    if any(r.family == "proximity" for r in table.devices):
        topics.append(_scan_topic(table))
    return tuple(topics)
