"""``ego ros2`` on the command line: the emulated robot joins the graph of the session
standing where rmw_zenohd would (``--router``), publishes, and withdraws when it ends."""

from __future__ import annotations

import subprocess
import threading

from helpers import ego_command, wait_until

from ego.zenoh_net.sessions import ZenohSettings, open_session
from tests.ros2.ros2_support import free_endpoint
from tests.ros2_node.bridge_support import key_of


def test_ego_ros2_serves_the_robot_until_its_duration() -> None:
    endpoint = free_endpoint()
    ros = open_session(ZenohSettings(listen=[endpoint], connect=[]))
    got = threading.Event()
    sub = ros.declare_subscriber(key_of("/robot/scan", "sensor_msgs/msg/LaserScan", "kilted"),
                                 lambda sample: got.set())  # fmt: skip

    def nodes() -> list[str]:
        replies = ros.liveliness().get("@ros2_lv/0/**", timeout=5)
        keys = [str(r.ok.key_expr) for r in replies if r.ok is not None]
        return [k.split("/", 7)[7] for k in keys if k.split("/")[5] == "NN"]

    try:
        proc = subprocess.Popen([*ego_command(), "ros2", "--port", "sim", "--router", endpoint,
                                 "--namespace", "robot", "--distro", "kilted",  # relative: /robot
                                 "--duration", "6"], stderr=subprocess.PIPE, text=True)  # fmt: skip
        try:
            assert wait_until(lambda: nodes() == ["%robot/epuck_driver"], 20)
            assert got.wait(10)
        finally:
            _, err = proc.communicate(timeout=30)
        assert proc.returncode == 0, err
        assert "as ROS 2 node /robot/epuck_driver (kilted, domain 0)" in err
        assert wait_until(lambda: nodes() == [], 5)
    finally:
        sub.undeclare()
        ros.close()


def test_ego_ros2_on_an_emulated_e_puck2_publishes_its_tof() -> None:
    """The e-puck2's tof row (the device table) gives the bridge its ``tof`` Range topic."""
    from rosbags.typesys import Stores, get_typestore

    endpoint = free_endpoint()
    ros = open_session(ZenohSettings(listen=[endpoint], connect=[]))
    ranges: list[float] = []
    store = get_typestore(Stores.ROS2_JAZZY)

    def take(sample: object) -> None:
        payload = bytes(sample.payload)  # type: ignore[attr-defined]
        ranges.append(store.deserialize_cdr(payload, "sensor_msgs/msg/Range").range)

    sub = ros.declare_subscriber(key_of("/tof", "sensor_msgs/msg/Range", "jazzy"), take)
    try:
        proc = subprocess.Popen([*ego_command(), "ros2", "--port", "sim", "--robot", "epuck2",
                                 "--router", endpoint, "--duration", "4"],
                                stderr=subprocess.PIPE, text=True)  # fmt: skip
        try:
            assert wait_until(lambda: len(ranges) >= 3, 20)
        finally:
            _, err = proc.communicate(timeout=30)
        assert proc.returncode == 0, err
        assert all(0.0 < r <= 2.0 for r in ranges), ranges  # metres, the sensor's 2 m reach
    finally:
        sub.undeclare()
        ros.close()
