"""The cmd_vel deadman's thread has an owner: the bridge's close joins it, and a program
that ends with its bridge still attached exits instead of waiting on it for ever (the
benchmarks' ROS 2 section unhooked its bridge without closing it, and CI hung at exit)."""

from __future__ import annotations

import subprocess
import sys
import textwrap
import threading

from ego.core.robot import Robot
from ego.ros2.participant import Participant
from ego.servers.ros2_node.bridge import Ros2Bridge
from ego.zenoh_net.sessions import ZenohSettings, open_session
from tests.ros2.ros2_support import free_endpoint


def _deadman_threads() -> list[threading.Thread]:
    return [t for t in threading.enumerate() if t.name.startswith("ego-ros2-deadman")]


def test_close_joins_the_deadman_thread() -> None:
    before = _deadman_threads()
    session = open_session(ZenohSettings(listen=[free_endpoint()]))
    try:
        with Robot("sim", seed=1, handle_signals=False) as robot:
            node = Participant(session, "epuck_driver")
            bridge = Ros2Bridge(robot, node).attach()
            started = [t for t in _deadman_threads() if t not in before]
            assert [t.name for t in started] == ["ego-ros2-deadman /epuck_driver"]
            bridge.close()
            assert not started[0].is_alive()
            bridge.close()  # again does nothing
            node.close()
    finally:
        session.close()


def test_a_program_that_leaves_its_bridge_attached_still_exits() -> None:
    program = textwrap.dedent(f"""
        from ego.core.robot import Robot
        from ego.ros2.participant import Participant
        from ego.servers.ros2_node.bridge import Ros2Bridge
        from ego.zenoh_net.sessions import ZenohSettings, open_session

        session = open_session(ZenohSettings(listen=[{free_endpoint()!r}]))
        robot = Robot("sim", seed=1, handle_signals=False)
        Ros2Bridge(robot, Participant(session, "epuck_driver")).attach()
        robot.step(64)
        print("attached", flush=True)
    """)
    done = subprocess.run([sys.executable, "-c", program], capture_output=True, text=True,
                          timeout=60)  # fmt: skip
    assert done.stdout == "attached\n", done.stderr
    assert done.returncode == 0, done.stderr
