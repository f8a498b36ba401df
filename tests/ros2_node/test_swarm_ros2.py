"""Issue 26, item 5: ``ego swarm --ros2`` puts N emulated robots in one ROS 2 graph under
the namespaces epuck0..N-1: each robot's node token, its own topics, and a Twist on
``/epuck1/cmd_vel`` drives robot 1 only."""

from __future__ import annotations

import subprocess
import time
from contextlib import ExitStack

from helpers import ego_command, wait_until
from zenoh.ext import Int64, z_serialize

from ego.app.cli import main
from ego.app.swarm import robot_name, robot_seed
from ego.servers.ros2_node.swarm import RosSwarm
from ego.zenoh_net.sessions import ZenohSettings, open_session
from tests.ros2.ros2_support import CdrWriter, free_endpoint
from tests.ros2_node.bridge_support import key_of


def _node_tokens(ros: object) -> list[str]:
    replies = ros.liveliness().get("@ros2_lv/0/**", timeout=5)  # type: ignore[attr-defined]
    keys = [str(r.ok.key_expr) for r in replies if r.ok is not None]
    return sorted(k.split("/", 7)[7] for k in keys if k.split("/")[5] == "NN")


def test_three_robots_each_a_node_in_its_namespace() -> None:
    with ExitStack() as stack:
        endpoint = free_endpoint()
        ros = open_session(ZenohSettings(listen=[endpoint], connect=[]))
        stack.callback(ros.close)
        session = open_session(ZenohSettings(listen=[free_endpoint()], connect=[endpoint]))
        stack.callback(session.close)
        seeds = [robot_seed(1, i) for i in range(3)]
        swarm = stack.enter_context(RosSwarm(3, session, seeds=seeds, name=robot_name))
        assert _node_tokens(ros) == [f"%epuck{i}/epuck_driver" for i in range(3)]
        heard: dict[str, int] = {}
        subs = [ros.declare_subscriber(key_of(f"/epuck{i}/ps0", "sensor_msgs/msg/Range", "jazzy"),
                                       lambda s, i=i: heard.__setitem__(f"epuck{i}", 1))
                for i in range(3)]  # fmt: skip
        assert wait_until(lambda: len(heard) == 3, 10), heard
        twist = ros.declare_publisher(key_of("/epuck1/cmd_vel", "geometry_msgs/msg/Twist", "jazzy"))
        payload = CdrWriter()
        for value in (0.05, 0.0, 0.0, 0.0, 0.0, 0.0):
            payload.write("float64", value)

        def driving() -> bool:
            attachment = z_serialize((Int64(1), Int64(time.time_ns()), bytes(16)))
            twist.put(payload.payload(), attachment=attachment)
            return swarm.robots[1].motors.speed != (0, 0)

        assert wait_until(driving, 5)
        assert [robot.motors.speed for robot in (swarm.robots[0], swarm.robots[2])] == [(0, 0)] * 2
        for sub in (*subs, twist):
            sub.undeclare()
        swarm.close()
        assert wait_until(lambda: _node_tokens(ros) == [], 5)


def test_ego_swarm_ros2_runs_the_robots_until_its_duration() -> None:
    endpoint = free_endpoint()
    ros = open_session(ZenohSettings(listen=[endpoint], connect=[]))
    try:
        proc = subprocess.Popen([*ego_command(), "swarm", "--ros2", "--robots", "2", "--router",
                                 endpoint, "--duration", "8"], stderr=subprocess.PIPE,
                                text=True)  # fmt: skip
        try:
            want = [f"%epuck{i}/epuck_driver" for i in range(2)]
            assert wait_until(lambda: _node_tokens(ros) == want, 20)
        finally:
            _, err = proc.communicate(timeout=30)
        assert proc.returncode == 0, err
        assert "2 emulated e-pucks as ROS 2 nodes /epuck0..epuck1/epuck_driver" in err
        assert wait_until(lambda: _node_tokens(ros) == [], 5)
    finally:
        ros.close()


def test_ego_swarm_ros2_runs_no_controller(capsys: object) -> None:
    assert main(["swarm", "--ros2", "avoid.py"]) == 1
    assert main(["swarm"]) == 1
