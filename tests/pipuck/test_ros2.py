"""Issue 33, item 4: ``ego ros2 --port pipuck`` on the Pi publishes epuck_ros2's topics on
the same robot, from the same sources: the IR ranges through the packet, ``imu`` from the
MPU-9250 with its gyro, ``tof`` from the VL53L0X and ``gs0`` from the ground module
(the emulated Pi-puck, reached through the shim; ROS 2 as rmw_zenoh's keys)."""

from __future__ import annotations

import subprocess
from collections.abc import Callable
from typing import Any

from helpers import ego_command, wait_until
from pipuck_support import env_of

from ego.zenoh_net.sessions import ZenohSettings, open_session
from firmware_sim.pipuck import PipuckEmulator
from tests.ros2.ros2_support import free_endpoint
from tests.ros2_node.bridge_support import key_of

TOPICS = {"/imu": "sensor_msgs/msg/Imu", "/tof": "sensor_msgs/msg/Range",
          "/gs0": "sensor_msgs/msg/Range", "/ps0": "sensor_msgs/msg/Range"}  # fmt: skip


def test_ego_ros2_on_a_pipuck_publishes_epuck_ros2s_topics(
    pipuck: Callable[..., PipuckEmulator],
) -> None:
    from rosbags.typesys import Stores, get_typestore

    emu = pipuck()
    endpoint = free_endpoint()
    ros = open_session(ZenohSettings(listen=[endpoint], connect=[]))
    store = get_typestore(Stores.ROS2_JAZZY)
    got: dict[str, list[Any]] = {topic: [] for topic in TOPICS}

    def taker(topic: str) -> Callable[[Any], None]:
        return lambda sample: got[topic].append(
            store.deserialize_cdr(bytes(sample.payload), TOPICS[topic])
        )

    subs = [ros.declare_subscriber(key_of(topic, kind, "jazzy"), taker(topic))
            for topic, kind in TOPICS.items()]  # fmt: skip
    try:
        proc = subprocess.Popen([*ego_command(), "ros2", "--port", "pipuck", "--router", endpoint,
                                 "--duration", "4"], env=env_of(emu),
                                stderr=subprocess.PIPE, text=True)  # fmt: skip
        try:
            assert wait_until(lambda: all(len(v) >= 3 for v in got.values()), 30), {
                k: len(v) for k, v in got.items()
            }
        finally:
            _, err = proc.communicate(timeout=30)
        assert proc.returncode == 0, err
    finally:
        for sub in subs:
            sub.undeclare()
        ros.close()
    imu = got["/imu"][-1]
    assert list(imu.angular_velocity_covariance) == [0.0] * 9  # the MPU-9250's gyro
    assert abs(imu.linear_acceleration.z - 9.81) < 1.0
    assert all(0.0 < m.range <= 2.0 for m in got["/tof"])  # metres
    assert got["/gs0"][-1].header.frame_id == "gs0"
    assert emu.truth.last_was_stop
