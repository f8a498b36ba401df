"""A robot on the emulator bridged to ROS 2 on loopback Zenoh, and what the tests read of
it: every step's truth, recorded by a step listener of the test's own after the bridge's.

The ``ros`` session is a Zenoh router on loopback, where rmw_zenohd and the ROS 2 nodes
are: the bridge's peer session connects to it as ``ego ros2 --router`` does.
"""

from __future__ import annotations

import json
import math
import threading
from collections.abc import Iterator
from contextlib import ExitStack, contextmanager
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from rosbags.typesys import Stores, get_typestore

from ego.core.robot import Robot
from ego.ros2.participant import Participant
from ego.servers.ros2_node.bridge import Ros2Bridge
from ego.servers.ros2_node.runner import NodeRunner
from ego.zenoh_net.sessions import ZenohSettings, open_session
from tests.ros2.ros2_support import free_endpoint

STORES = {"humble": Stores.ROS2_HUMBLE, "jazzy": Stores.ROS2_JAZZY, "kilted": Stores.ROS2_KILTED}


def key_of(topic: str, type_name: str, distro: str, domain: int = 0) -> str:
    """The data key as rmw_zenoh's TopicInfo spells it (liveliness_utils.cpp:86-93), the
    hash from rosbags' store directly (Humble: the constant, rmw_publisher_data.cpp:73-75)."""
    pkg, kind, name = type_name.split("/")
    if distro == "humble":
        hash_ = "TypeHashNotSupported"
    else:
        hash_ = get_typestore(STORES[distro]).hash_rihs01(type_name)
    return f"{domain}/{topic.strip('/')}/{pkg}::{kind}::dds_::{name}_/{hash_}"


@dataclass
class Truth:
    """What the robot read at one step, and where the emulator says it was."""

    proximity: tuple[int, ...]
    light: tuple[int, ...]
    floor: tuple[int, ...]
    acceleration: tuple[float, float, float]
    wheels_rad: tuple[float, float]
    pose: tuple[float, float, float]
    image: Any


@dataclass
class Bridged:
    robot: Robot
    bridge: Ros2Bridge
    node: Participant
    runner: NodeRunner
    ros: Any
    distro: str
    truths: dict[int, Truth] = field(default_factory=dict)
    start: tuple[float, float, float] = (0.0, 0.0, 0.0)
    #: Where the ``ros`` session listens (the router's place).
    endpoint: str = ""
    lock: threading.Lock = field(default_factory=threading.Lock)

    def record(self, robot: Robot) -> None:
        stamp = self.bridge.last_stamp_ns
        if stamp is None or not robot.proximity.has_values or not robot.encoders.has_values:
            return
        truth = robot.ground_truth
        assert truth is not None
        pose = truth.pose()
        assert pose is not None
        camera = robot.open_camera
        image = camera.image.copy() if camera is not None and camera.frame_count else None
        with self.lock:
            self.truths[stamp] = Truth(
                tuple(robot.proximity.values[:8]), tuple(robot.light.values[:8]),
                tuple(robot.floor.values[:3]), robot.accelerometer.acceleration_mps2,
                robot.encoders.radians, (pose.x_m, pose.y_m, pose.theta_rad), image,
            )  # fmt: skip

    def relative_pose(self, stamp: int) -> tuple[float, float, float]:
        """The true pose at ``stamp`` in the frame of the pose at the start (odom's)."""
        x0, y0, t0 = self.start
        x, y, t = self.truths[stamp].pose
        dx, dy = x - x0, y - y0
        c, s = math.cos(-t0), math.sin(-t0)
        return (c * dx - s * dy, s * dx + c * dy, math.remainder(t - t0, 2 * math.pi))


def router_session(endpoint: str) -> Any:
    """A Zenoh router on loopback, where rmw_zenohd stands in a ROS 2 system (mode
    "router", listening on ``endpoint``, no multicast scouting): the ROS side's
    subscribers and publishers are declared on it, and the bridge reaches them through it."""
    import zenoh

    config = zenoh.Config()
    config.insert_json5("mode", json.dumps("router"))
    config.insert_json5("listen/endpoints", json.dumps([endpoint]))
    config.insert_json5("scouting/multicast/enabled", "false")
    return zenoh.open(config)


@contextmanager
def bridged(distro: str = "jazzy", namespace: str = "/", deadline_s: float = 0.5,
            **sim: Any) -> Iterator[Bridged]:  # fmt: skip
    """The emulated robot as ROS 2 node ``epuck_driver``, stepped by its runner."""
    with ExitStack() as stack:
        endpoint = free_endpoint()
        ros = router_session(endpoint)
        stack.callback(ros.close)
        session = open_session(ZenohSettings(listen=[free_endpoint()], connect=[endpoint]))
        stack.callback(session.close)
        robot = Robot("sim", seed=1, **sim)
        stack.callback(robot.close)
        truth = robot.ground_truth
        assert truth is not None
        pose = truth.pose()
        assert pose is not None
        node = Participant(session, "epuck_driver", namespace=namespace, distro=distro)
        stack.callback(node.close)
        bridge = Ros2Bridge(robot, node, deadline_s=deadline_s).attach()
        stack.callback(bridge.close)
        out = Bridged(robot, bridge, node, NodeRunner(robot, 64, "test"), ros, distro,
                      start=(pose.x_m, pose.y_m, pose.theta_rad), endpoint=endpoint)  # fmt: skip
        robot.add_step_listener(out.record)
        out.runner.start()
        stack.callback(out.runner.close)
        yield out


def rgb(image: Any) -> bytes:
    return bytes(np.ascontiguousarray(image).reshape(-1))
