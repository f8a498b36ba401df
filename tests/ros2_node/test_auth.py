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


class Graph:
    """A router with a dictionary (and an access-control policy, if given), ``ego ros2``
    with its credentials, and what a credentialed ROS node hears of the wheels."""

    def __init__(self, tmp_path: Path, acl: dict[str, Any] | None = None) -> None:
        import zenoh

        self.users = tmp_path / "users.txt"
        self.users.write_text("".join(f"{u}:{p}\n" for u, p in USERS.items()))
        ego_config = tmp_path / "ego.json5"
        ego_config.write_text(json.dumps({"transport": {"auth": {"usrpwd": {
            "user": "ego", "password": USERS["ego"]}}}}))  # fmt: skip
        self.endpoint = free_endpoint()
        more = {"access_control": acl} if acl else {}
        self.router = zenoh.open(_config("router", [self.endpoint], [], {
            "user": "router", "password": "router-secret",
            "dictionary_file": str(self.users)}, **more))  # fmt: skip
        self.velocities: list[float] = []
        self.ros = self.peer("teleop")
        store = get_typestore(Stores.ROS2_JAZZY)

        def take(sample: Any) -> None:
            message = store.deserialize_cdr(bytes(sample.payload), "sensor_msgs/msg/JointState")
            self.velocities.append(float(max(abs(v) for v in message.velocity)))

        self.joints = self.ros.declare_subscriber(
            key_of("/joint_states", "sensor_msgs/msg/JointState", "jazzy"), take)  # fmt: skip
        self.proc = subprocess.Popen([*ego_command(), "ros2", "--port", "sim", "--router",
                                      self.endpoint, "--zenoh-config", str(ego_config),
                                      "--duration", "30"], stderr=subprocess.PIPE,
                                     text=True)  # fmt: skip
        self.sessions = [self.ros, self.router]

    def peer(self, user: str | None, password: str | None = None) -> Any:
        """A ROS node's session: ``user`` with its password (or ``password``), the
        dictionary too (docs/ros2.md); None: no credentials at all."""
        if user is None:
            session = _ros_peer(self.endpoint, None)
        else:
            session = _ros_peer(self.endpoint, {"user": user,
                                                "password": password or USERS[user],
                                                "dictionary_file": str(self.users)})  # fmt: skip
        if hasattr(self, "sessions"):
            self.sessions.insert(0, session)
        return session

    def still_while(self, session: Any) -> bool:
        """Whether the wheels stay still while ``session`` publishes Twists for 0.5 s
        (and a few joint states after)."""
        intruder = Teleop(session, key_of("/cmd_vel", TWIST, "jazzy"))
        for _ in range(10):
            intruder.send(0.1)
            time.sleep(0.05)
        intruder.close()
        heard = len(self.velocities)
        assert wait_until(lambda: len(self.velocities) >= heard + 5, 10)
        return max(self.velocities) == 0.0

    def drives(self, session: Any) -> bool:
        teleop = Teleop(session, key_of("/cmd_vel", TWIST, "jazzy"))

        def driving() -> bool:
            teleop.send(0.05)
            return self.velocities[-1] > 1.0  # rad/s: 0.05 m/s on 20.5 mm wheels is 2.4

        try:
            return wait_until(driving, 10)
        finally:
            teleop.close()

    def close(self) -> str:
        self.proc.terminate()
        _, err = self.proc.communicate(timeout=30)
        self.joints.undeclare()
        for session in self.sessions:
            session.close()
        return err


def test_a_credentialed_ros_node_drives_the_robot_and_a_stranger_cannot(tmp_path: Path) -> None:
    graph = Graph(tmp_path)
    try:
        # rmw_zenoh's default peer with only its user and password, as the issue tried.
        ros = _ros_peer(graph.endpoint, {"user": "teleop", "password": USERS["teleop"]})
        graph.sessions.insert(0, ros)
        stranger, wrong = graph.peer(None), graph.peer("teleop", "guessed")
        assert wait_until(lambda: len(graph.velocities) >= 5, 20), "the bridge never came"
        # The strangers were never let in: no router, no peer, nothing their puts reach.
        for session in (stranger, wrong):
            assert list(session.info.routers_zid()) == [] and list(session.info.peers_zid()) == []
            assert graph.still_while(session)
        assert graph.drives(ros), graph.velocities[-5:]
    finally:
        err = graph.close()
    assert "as ROS 2 node /epuck_driver" in err, err


def test_an_access_control_policy_keeps_cmd_vel_to_the_teleop(tmp_path: Path) -> None:
    """docs/ros2.md's policy: the router denies ``put`` on cmd_vel (ingress) to the
    viewer, an authenticated user; the teleop still drives. ego, a client, hears
    only through the router, so no direct peer link goes around the policy."""
    USERS["viewer"] = "viewer-secret-3"
    acl = {"enabled": True, "default_permission": "allow",
           "rules": [{"id": "no cmd_vel", "permission": "deny", "flows": ["ingress"],
                      "messages": ["put"], "key_exprs": ["*/cmd_vel/**", "*/*/cmd_vel/**"]}],
           "subjects": [{"id": "viewers", "usernames": ["viewer"]}],
           "policies": [{"rules": ["no cmd_vel"], "subjects": ["viewers"]}]}  # fmt: skip
    graph = Graph(tmp_path, acl)
    try:
        viewer = graph.peer("viewer")
        assert wait_until(lambda: len(graph.velocities) >= 5, 20), "the bridge never came"
        assert list(viewer.info.routers_zid()) != []  # let in: authenticated
        assert graph.still_while(viewer)
        assert graph.drives(graph.ros), graph.velocities[-5:]
    finally:
        graph.close()
        del USERS["viewer"]


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
