"""What the emulator knows of the world reaches the library through ego's typed protocol
(ego.core.ground_truth), never as an untyped object read attribute by attribute.

The sim backend hands a :class:`GroundTruth` of ego's types; the readers (telemetry, the
dashboard's world, the faces' ground-truth devices, the radio) are shown to need nothing
beyond the protocol: a double written against it alone serves them.
"""

from __future__ import annotations

import math
from collections.abc import Iterator

import numpy as np
import pytest
from numpy.typing import NDArray

import ego
from ego.backends.zenoh_remote import _Truth
from ego.controller.gps import GPS
from ego.controller.radio import _true_pose
from ego.core.backend import Opened
from ego.core.ground_truth import Box, GroundTruth, Layout, TruePose, TrueWorld
from ego.core.robot import Robot
from ego.core.telemetry import describe_world, world_pose
from firmware_sim.ego_backend import EmulatorTruth


class _World:
    """A world written against the protocol only: one box, a half-white floor."""

    def layout(self) -> Layout:
        return Layout(0.4, 0.3, (Box(0.1, -0.2, 0.05, 0.02, 0.5, (10, 20, 30)),), (0.2, 0.1))

    def floor_reflectance(
        self, x_m: NDArray[np.float64], y_m: NDArray[np.float64]
    ) -> NDArray[np.float64]:
        return np.where(x_m > 0, 1.0, 0.0)

    def declared_devices(self) -> frozenset[str]:
        return frozenset({"gps"})

    def device_values(self, name: str) -> tuple[float, float, float]:
        return (0.25, -0.125, 0.0486)

    def touching(self) -> bool:
        return True

    camera_size = (160, 120)
    distance_travelled_m = 1.5
    closest_approach_m = 0.01


class _Truth_:
    def __init__(self, world: TrueWorld | None) -> None:
        self.true_world = world

    def pose(self) -> TruePose:
        return TruePose(0.123456789, -0.5, math.pi / 2)


def _typed(truth: GroundTruth) -> GroundTruth:
    return truth  # mypy checks that the doubles follow the protocol


@pytest.fixture
def sim_robot() -> Iterator[ego.Robot]:
    with ego.Robot("sim", seed=3) as robot:
        yield robot


def test_the_seams_are_typed_not_any() -> None:
    assert Opened.__annotations__["ground_truth"] == "GroundTruth | None"
    assert Robot.ground_truth.fget.__annotations__["return"] == "GroundTruth | None"


def test_the_sim_backend_hands_ego_types(sim_robot: ego.Robot) -> None:
    truth = sim_robot.ground_truth
    assert truth is not None
    pose = truth.pose()
    assert type(pose) is TruePose and (pose.x_m, pose.y_m) == pytest.approx((0.0, 0.0))
    world = truth.true_world
    assert world is not None
    layout = world.layout()
    assert type(layout) is Layout and layout.boxes and all(type(b) is Box for b in layout.boxes)
    assert isinstance(world.declared_devices(), frozenset)
    assert world.distance_travelled_m == 0.0 and world.camera_size is None
    assert isinstance(truth, EmulatorTruth) and truth.world.arena.half_size_m == layout.half_x_m


def test_the_sim_robots_pose_follows_the_world(sim_robot: ego.Robot) -> None:
    sim_robot.motors.set_speed(500, 500)
    for _ in range(20):
        sim_robot.step(32)
    truth = sim_robot.ground_truth
    assert truth is not None and truth.true_world is not None
    pose = truth.pose()
    assert pose is not None and pose.x_m > 0.01  # driven forward along +x
    assert truth.true_world.distance_travelled_m == pytest.approx(math.hypot(pose.x_m, pose.y_m),
                                                                   rel=0.1)  # fmt: skip
    sim_robot.motors.set_speed(0, 0)
    sim_robot.step(32)


def test_the_world_is_drawn_from_the_protocol_alone() -> None:
    truth = _typed(_Truth_(_World()))
    drawn = describe_world(truth, floor_cells=8)
    assert drawn is not None
    assert (drawn["half_x"], drawn["half_y"], drawn["lamp"]) == (0.4, 0.3, [0.2, 0.1])
    assert drawn["boxes"] == [{"x": 0.1, "y": -0.2, "hx": 0.05, "hy": 0.02, "yaw": 0.5,
                               "rgb": [10, 20, 30]}]  # fmt: skip
    assert drawn["start"] == [0.12346, -0.5, round(math.pi / 2, 5)]
    assert drawn["floor_png"].startswith("data:image/png;base64,")
    assert world_pose(truth) == drawn["start"]
    assert describe_world(_typed(_Truth_(None))) is None  # a pose, but no world to draw
    assert describe_world(None) is None and world_pose(None) is None


class _Sent:
    """What a Zenoh channel exposes of the node's attachment: the last true pose sent."""

    def __init__(self, truth: list[float] | None) -> None:
        self.truth = truth


def test_a_zenoh_robot_knows_the_pose_its_node_sent_and_no_world() -> None:
    known = _typed(_Truth(_Sent([0.25, -0.125, 1.0])))  # type: ignore[arg-type]
    assert known.pose() == TruePose(0.25, -0.125, 1.0) and known.true_world is None
    assert _typed(_Truth(_Sent(None))).pose() is None  # type: ignore[arg-type]
    assert describe_world(known) is None and world_pose(known) == [0.25, -0.125, 1.0]


class _Core:
    """What the radio and the faces read of a core robot: its ground truth."""

    def __init__(self, truth: GroundTruth | None) -> None:
        self.ground_truth = truth


def test_the_radio_reads_the_pose_through_the_protocol() -> None:
    assert _true_pose(_Core(_Truth_(None))) == [0.123456789, -0.5, math.pi / 2]  # type: ignore[arg-type]
    assert _true_pose(_Core(None)) is None  # type: ignore[arg-type]


def test_the_faces_gps_reads_what_the_world_says_its_gps_reads() -> None:
    """A GPS reads the world's device_values (its mount and the file's frame are the
    world's to know), not the robot's centre: the double's pose is elsewhere."""
    gps = GPS(_Core(_Truth_(_World())), "gps", strict=True)  # type: ignore[arg-type]
    assert all(math.isnan(v) for v in gps.getValues())  # disabled: NaN, as Webots
    gps.enable(32)
    assert gps.getValues() == [0.25, -0.125, 0.0486]
