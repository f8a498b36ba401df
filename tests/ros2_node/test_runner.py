"""The runner that steps a bridged robot: an error in a step ends its thread and is kept
for its owner (``ego ros2`` raises it), and close() joins the thread."""

from __future__ import annotations

import threading

from ego.core.robot import Robot
from ego.servers.ros2_node.runner import NodeRunner


def test_an_error_in_a_step_ends_the_runner_and_is_kept_for_its_owner() -> None:
    with Robot("sim", seed=1) as robot:
        calls = []

        def failing(_: Robot) -> None:
            calls.append(1)
            if len(calls) == 3:
                raise RuntimeError("publishing failed")

        robot.add_step_listener(failing)
        runner = NodeRunner(robot, 16, "failing").start()
        assert runner.ended.wait(10)
        assert isinstance(runner.error, RuntimeError) and len(calls) == 3
        runner.close()
        assert not any(t.name == "ego-ros2 failing" for t in threading.enumerate())
