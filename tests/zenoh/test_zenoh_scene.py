"""A node's scene over Zenoh (``ego/NAME/scene``): a controller reached through zenoh://
gets its world's scene where the node serves one (ego swarm's), and none where it does
not (``ego serve --zenoh`` of a robot), where the Supervisor still says so."""

from __future__ import annotations

import math

import pytest
from zenoh_support import served_node

import ego


def test_a_node_serving_its_scene_gives_the_controller_a_supervisor() -> None:
    with served_node("s1", scene=True) as served:
        robot = ego.Robot("zenoh://s1", zenoh_connect=[served.endpoint])
        with robot:
            scene = robot.scene
            assert scene is not None
            truth = served.world.snapshot()
            x, y, _, yaw = scene.pose("")
            assert (x, y, yaw) == (truth.x_m, truth.y_m, truth.theta_rad)
            scene.set_pose("", (0.1, -0.05, 0.0), 1.0)
            assert scene.vertical == (0.0, 0.0, 1.0)
            moved = served.world.snapshot()
            assert math.isclose(moved.x_m, 0.1) and math.isclose(moved.theta_rad, 1.0)
            with pytest.raises(KeyError, match="no solid named 'NOPE'"):
                scene.pose("NOPE")
            scene.reset()
            back = served.world.snapshot()
            assert (back.x_m, back.y_m) == (truth.x_m, truth.y_m)


def test_a_node_without_a_scene_gives_none() -> None:
    # The Supervisor face then refuses each simulation call (tests/faces: "none to
    # supervise"), as on a real robot.
    with served_node("s2") as served:
        robot = ego.Robot("zenoh://s2", zenoh_connect=[served.endpoint])
        with robot:
            assert robot.scene is None
