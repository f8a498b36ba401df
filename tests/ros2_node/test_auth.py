"""Issue 32, item 2: who may drive the robot through ROS 2.

End to end, with Zenoh's user-password authentication as docs/ros2.md sets it up: a
router standing where rmw_zenohd is (its ``dictionary_file`` lists who may connect),
``ego ros2`` with its own user and password (``--zenoh-config``), a ROS node in
rmw_zenoh's default session mode (a peer, listening on localhost, gossip autoconnecting
to peers) with the right credentials, and a stranger. Before, ego was a peer too: the
credentialed node and ego each refused the other's direct link (neither holds the
other's dictionary) and Zenoh routed nothing, silently. Now ego is a client of the
router: the credentialed node drives the robot, the stranger is not let in at all.
And a router off loopback without credentials is refused in one line unless
``--allow-unauthenticated-router`` says so.
"""

from __future__ import annotations

import json
import subprocess
import time
from pathlib import Path
from typing import Any

import pytest
from helpers import ego_command, wait_until
from rosbags.typesys import Stores, get_typestore

from ego.errors import InsecureSecretError
from tests.ros2.ros2_support import free_endpoint
from tests.ros2_node.bridge_support import key_of
from tests.ros2_node.flood_support import TWIST, Teleop

USERS = {"ego": "ego-secret-1", "teleop": "teleop-secret-2"}


def _config(mode: str, listen: list[str], connect: list[str], usrpwd: dict[str, str] | None,
            **more: Any) -> Any:  # fmt: skip
    import zenoh

    config = zenoh.Config()
    settings = {"mode": mode, "listen/endpoints": listen, "connect/endpoints": connect,
                "scouting/multicast/enabled": False, **more}  # fmt: skip
    if usrpwd is not None:
        settings["transport/auth/usrpwd"] = usrpwd
    for key, value in settings.items():
        config.insert_json5(key, json.dumps(value))
    return config


def _ros_peer(router: str, usrpwd: dict[str, str] | None) -> Any:
    """A ROS 2 node's session as rmw_zenoh opens it by default
    (config/DEFAULT_RMW_ZENOH_SESSION_CONFIG.json5: a peer listening on localhost,
    connecting to the router, gossip on, autoconnecting to routers and peers)."""
    import zenoh

    return zenoh.open(_config("peer", ["tcp/localhost:0"], [router], usrpwd,
                              **{"scouting/gossip/enabled": True,
                                 "scouting/gossip/autoconnect":
                                     {"router": [], "peer": ["router", "peer"]}}))  # fmt: skip


def test_a_credentialed_ros_node_drives_the_robot_and_a_stranger_cannot(tmp_path: Path) -> None:
    import zenoh

    users = tmp_path / "users.txt"
    users.write_text("".join(f"{user}:{password}\n" for user, password in USERS.items()))
    ego_config = tmp_path / "ego.json5"
    ego_config.write_text(json.dumps({"transport": {"auth": {"usrpwd": {
        "user": "ego", "password": USERS["ego"]}}}}))  # fmt: skip
    endpoint = free_endpoint()
    router = zenoh.open(_config("router", [endpoint], [], {
        "user": "router", "password": "router-secret", "dictionary_file": str(users)}))  # fmt: skip
    velocities: list[float] = []
    store = get_typestore(Stores.ROS2_JAZZY)
    ros = _ros_peer(endpoint, {"user": "teleop", "password": USERS["teleop"]})
    stranger = _ros_peer(endpoint, None)
    wrong = _ros_peer(endpoint, {"user": "teleop", "password": "guessed"})

    def take(sample: Any) -> None:
        message = store.deserialize_cdr(bytes(sample.payload), "sensor_msgs/msg/JointState")
        velocities.append(float(max(abs(v) for v in message.velocity)))

    joints = ros.declare_subscriber(key_of("/joint_states", "sensor_msgs/msg/JointState",
                                           "jazzy"), take)  # fmt: skip
    proc = subprocess.Popen([*ego_command(), "ros2", "--port", "sim", "--router", endpoint,
                             "--zenoh-config", str(ego_config), "--duration", "20"],
                            stderr=subprocess.PIPE, text=True)  # fmt: skip
    try:
        assert wait_until(lambda: len(velocities) >= 5, 20), "the bridge never reached the node"
        # The strangers were never let in: no router, no peer, nothing their puts reach.
        for session in (stranger, wrong):
            assert list(session.info.routers_zid()) == [] and list(session.info.peers_zid()) == []
        for session in (stranger, wrong):
            intruder = Teleop(session, key_of("/cmd_vel", TWIST, "jazzy"))
            for _ in range(10):
                intruder.send(0.1)
                time.sleep(0.05)
            intruder.close()
        heard = len(velocities)
        assert wait_until(lambda: len(velocities) >= heard + 5, 10)
        assert max(velocities) == 0.0  # the wheels never turned
        teleop = Teleop(ros, key_of("/cmd_vel", TWIST, "jazzy"))

        def driving() -> bool:
            teleop.send(0.05)
            return velocities[-1] > 1.0  # rad/s: 0.05 m/s on 20.5 mm wheels is 2.4

        assert wait_until(driving, 10), velocities[-5:]
        teleop.close()
    finally:
        proc.terminate()
        _, err = proc.communicate(timeout=30)
        joints.undeclare()
        for session in (wrong, stranger, ros, router):
            session.close()
    assert "as ROS 2 node /epuck_driver" in err, err


def test_a_router_off_loopback_without_credentials_is_refused_in_one_line() -> None:
    proc = subprocess.run([*ego_command(), "ros2", "--port", "sim", "--router",
                           "tcp/192.0.2.7:7447", "--duration", "1"],
                          capture_output=True, text=True, timeout=60)  # fmt: skip
    assert proc.returncode != 0
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1, lines
    assert "anyone who reaches that router can drive the robot" in lines[0]
    assert "--allow-unauthenticated-router" in lines[0]


def test_what_counts_as_credentials(tmp_path: Path) -> None:
    from ego.servers.ros2_node.router import router_config

    remote = ["tcp/192.0.2.7:7447"]
    with pytest.raises(InsecureSecretError, match="allow-unauthenticated-router"):
        router_config(remote)
    dictionary_only = tmp_path / "dictionary.json5"  # the acceptor's list, not ego's proof
    dictionary_only.write_text(json.dumps({"transport": {"auth": {"usrpwd": {
        "dictionary_file": str(tmp_path / "users.txt")}}}}))  # fmt: skip
    with pytest.raises(InsecureSecretError):
        router_config(remote, str(dictionary_only))
    allowed = router_config(remote, allow_unauthenticated=True)  # said so: accepted
    assert json.loads(allowed.get_json("mode")) == "client"
    credentialed = tmp_path / "ego.json5"
    credentialed.write_text(json.dumps({"transport": {"auth": {"usrpwd": {
        "user": "ego", "password": "ego-secret-1"}}}}))  # fmt: skip
    config = router_config(remote, str(credentialed))
    assert json.loads(config.get_json("connect/endpoints")) == remote
    assert json.loads(config.get_json("listen/endpoints")) == []  # nothing connects to ego
    assert router_config(["tcp/127.0.0.1:7447"]) is not None  # loopback: this machine's
