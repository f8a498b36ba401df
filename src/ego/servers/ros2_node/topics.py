"""Which topics the bridge publishes and subscribes: epuck_ros2's, one row each, each
naming the devices of the device table it needs (no I/O).

A row is published only where every device it names is one the robot serves
(``robot.device_names``, derived from :mod:`ego.devices.table` and the firmware's
profile): ``tof`` appears on a robot whose table has a ``tof`` device, ``gs0..gs2`` where
the firmware reads the ground module. Names and types follow
cyberbotics/epuck_ros2@91ff8a1 ``epuck_ros2_driver/src/driver.cpp:139-161`` and
``epuck_ros2_camera/src/camera.cpp:73-77``; every publisher and subscription there has
depth 1 (reliable, volatile: rclcpp's default with a depth), tf2_ros's broadcaster depth
100 (``DynamicBroadcasterQoS``) and its static one depth 1, transient local. The driver
names ``/gs0..2`` and ``/led0..7`` absolute; ego resolves them in the node's namespace
like the others, so that the robots of a swarm keep theirs apart (in the root namespace
the names are the driver's).
"""

from __future__ import annotations

from collections.abc import Callable, Collection
from dataclasses import dataclass
from typing import Any

from ego.ros2.qos import Durability, QoS
from ego.servers.ros2_node.build import Messages
from ego.servers.ros2_node.reading import Reading

__all__ = ["PUBLISHED", "SUBSCRIBED", "Published", "Subscribed", "served"]

#: rclcpp's ``create_publisher(name, 1)``: keep last 1, reliable, volatile.
DEPTH_1 = QoS(depth=1)
#: tf2_ros::DynamicBroadcasterQoS (depth 100) and StaticBroadcasterQoS.
TF_QOS = QoS(depth=100)
TF_STATIC_QOS = QoS(depth=1, durability=Durability.TRANSIENT_LOCAL)
_WHEELS = ("left wheel sensor", "right wheel sensor")
_IR = tuple(f"ps{i}" for i in range(8))

Build = Callable[[Messages, Reading, float], Any]


@dataclass(frozen=True, slots=True)
class Published:
    """A topic the bridge publishes: name (relative), type, QoS, the devices it needs,
    how its message is built from a step's reading (None: nothing this step), and
    whether it goes out only while a subscriber listens (the camera's)."""

    name: str
    type_name: str
    qos: QoS
    needs: tuple[str, ...]
    build: Build
    on_demand: bool = False


@dataclass(frozen=True, slots=True)
class Subscribed:
    """A topic the bridge takes commands from."""

    name: str
    type_name: str
    qos: QoS
    needs: tuple[str, ...]


def _when(field: str, build: Build) -> Build:
    """``build`` if the reading has ``field``, else nothing this step."""
    return lambda m, r, period: None if getattr(r, field) is None else build(m, r, period)


def _indexed(field: str, method: str, i: int) -> Build:
    return _when(field, lambda m, r, _: getattr(m, method)(r, i))


PUBLISHED: tuple[Published, ...] = (
    *(Published(f"ps{i}", "sensor_msgs/msg/Range", DEPTH_1, (f"ps{i}",),
                _indexed("proximity", "proximity", i)) for i in range(8)),
    Published("tof", "sensor_msgs/msg/Range", DEPTH_1, ("tof",),
              _when("tof_m", lambda m, r, _: m.tof(r))),
    *(Published(f"ls{i}", "sensor_msgs/msg/Illuminance", DEPTH_1, (f"ls{i}",),
                _indexed("light", "illuminance", i)) for i in range(8)),
    *(Published(f"gs{i}", "sensor_msgs/msg/Range", DEPTH_1, (f"gs{i}",),
                _indexed("floor", "ground", i)) for i in range(3)),
    Published("scan", "sensor_msgs/msg/LaserScan", DEPTH_1, _IR,
              _when("proximity", lambda m, r, period: m.scan(r, period))),
    Published("imu", "sensor_msgs/msg/Imu", DEPTH_1, ("accelerometer",),
              _when("acceleration", lambda m, r, _: m.imu(r))),
    Published("odom", "nav_msgs/msg/Odometry", DEPTH_1, _WHEELS,
              _when("odometry", lambda m, r, _: m.odometry(r))),
    Published("tf", "tf2_msgs/msg/TFMessage", TF_QOS, _WHEELS,
              _when("odometry", lambda m, r, _: m.tf(r))),
    Published("joint_states", "sensor_msgs/msg/JointState", DEPTH_1, _WHEELS,
              _when("wheels_rad", lambda m, r, _: m.joint_states(r))),
    Published("image_raw", "sensor_msgs/msg/Image", DEPTH_1, ("camera",),
              _when("image", lambda m, r, _: m.image(r)), on_demand=True),
    Published("image_raw/compressed", "sensor_msgs/msg/CompressedImage", DEPTH_1,
              ("camera",), _when("jpeg", lambda m, r, _: m.compressed(r, r.jpeg or b"")),
              on_demand=True),
    Published("camera_info", "sensor_msgs/msg/CameraInfo", DEPTH_1, ("camera",),
              _when("image", lambda m, r, _: m.camera_info(r))),
)  # fmt: skip

#: The static transforms (driver.cpp:163-235), sent again every second: ego's publisher
#: keeps no history for late joiners (ego/ros2/FORMATS.md, "Not supported").
TF_STATIC = Published("tf_static", "tf2_msgs/msg/TFMessage", TF_STATIC_QOS, (),
                      lambda m, r, _: None)  # fmt: skip

SUBSCRIBED: tuple[Subscribed, ...] = (
    Subscribed("cmd_vel", "geometry_msgs/msg/Twist", DEPTH_1,
               ("left wheel motor", "right wheel motor")),
    *(Subscribed(f"led{i}", "std_msgs/msg/Bool" if i % 2 == 0 else "std_msgs/msg/Int32",
                 DEPTH_1, (f"led{i}",)) for i in range(8)),
)  # fmt: skip


def served(rows: tuple[Any, ...], devices: Collection[str]) -> list[Any]:
    """The rows of ``rows`` whose every needed device is among ``devices``."""
    return [row for row in rows if all(name in devices for name in row.needs)]
