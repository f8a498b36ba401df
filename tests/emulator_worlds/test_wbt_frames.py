"""A Webots world whose arena stands off the origin and turned, and one declared NUE:
loaded into the emulator's frame (the arena's, ENU), the walls where Webots puts them,
and what a GPS and a Compass in the E-puck's slots read, in the file's own frame."""

from __future__ import annotations

import math
from pathlib import Path

import pytest
from wbt_frame_worlds import NUE_WORLD, OFF_ORIGIN

from firmware_sim.scene import Scene
from firmware_sim.true_devices import device_values
from firmware_sim.world import World
from firmware_sim.worlds import load_world


def _load(tmp_path: Path, text: str) -> World:
    path = tmp_path / "world.wbt"
    path.write_text(text)
    return load_world(path, seed=1)


def test_an_arena_off_the_origin_has_its_walls_where_webots_puts_them(tmp_path: Path) -> None:
    world = _load(tmp_path, OFF_ORIGIN)
    assert world.arena.half_extents == pytest.approx((0.5, 0.25))
    frame = world.frame
    # From the world point (2, 1.3) looking along world +y: the arena's own +x, whose
    # wall stands at 0.5 m from its centre (2, 1): 0.2 m away.
    assert world.ray_distance(*frame.into_arena(2.0, 1.3, math.pi / 2)) == pytest.approx(
        0.2, abs=1e-4
    )
    # Along world -x from (2.1, 1): the arena's own +y, its 0.5 m side's wall at 0.25.
    assert world.ray_distance(*frame.into_arena(2.1, 1.0, math.pi)) == pytest.approx(
        0.25 + 0.1, abs=1e-4
    )
    # The robot and the crate stand where the world says, in the world's frame.
    pose = world.snapshot()
    assert frame.to_file(pose.x_m, pose.y_m, 0.0, pose.theta_rad) == pytest.approx(
        (1.9, 0.9, 0.0, math.pi), abs=1e-6
    )
    scene = Scene(world)
    assert scene.pose("CRATE") == pytest.approx((2.1, 1.3, 0.05, math.pi / 2), abs=1e-6)
    (crate,) = world.blocks
    assert (crate.x_m, crate.y_m, crate.yaw_rad) == pytest.approx((0.3, -0.1, 0.0), abs=1e-6)


def test_a_supervisor_moves_a_solid_in_the_turned_arenas_world_frame(tmp_path: Path) -> None:
    world = _load(tmp_path, OFF_ORIGIN)
    scene = Scene(world)
    scene.set_pose("CRATE", (1.8, 1.2, 0.05), 0.3)
    assert scene.pose("CRATE") == pytest.approx((1.8, 1.2, 0.05, 0.3), abs=1e-9)
    (crate,) = world.blocks
    assert (crate.x_m, crate.y_m) == pytest.approx((0.2, 0.2))


def test_a_gps_and_compass_in_the_turret_slot_read_the_world_frame(tmp_path: Path) -> None:
    world = _load(tmp_path, OFF_ORIGIN)
    assert world.declared_devices() == {"gps", "compass"}
    # The turret slot sits at (-0.0095, 0, 0.0486) on the robot; the robot faces world -x.
    assert device_values(world, "gps") == pytest.approx((1.9095, 0.9, 0.0486), abs=1e-6)
    assert device_values(world, "compass") == pytest.approx((0.0, -1.0, 0.0), abs=1e-6)


def test_an_nue_world_is_converted_as_webots_converts_it(tmp_path: Path) -> None:
    world = _load(tmp_path, NUE_WORLD)
    # floorSize 1 0.6: 1 m along the old x, which Webots' converter makes the new -y.
    assert world.arena.half_extents == pytest.approx((0.3, 0.5))
    (box,) = world.blocks
    assert (box.x_m, box.y_m, box.yaw_rad) == pytest.approx((0.1, -0.2, 0.5))
    assert box.half_extents == pytest.approx((0.02, 0.05))  # size x, y, z -> z, x, y
    assert box.height_m == pytest.approx(0.05)
    pose = world.snapshot()
    assert (pose.x_m, pose.y_m, pose.theta_rad) == pytest.approx((-0.2, 0.1, 1.0))


def test_an_nue_worlds_poses_are_answered_in_its_own_numbers(tmp_path: Path) -> None:
    world = _load(tmp_path, NUE_WORLD)
    scene = Scene(world)
    assert scene.vertical == (0.0, 1.0, 0.0)
    assert scene.pose("EPUCK") == pytest.approx((-0.1, 0.0, 0.2, 1.0))
    assert scene.pose("BOX") == pytest.approx((0.2, 0.025, -0.1, 0.5))
    scene.set_pose("BOX", (0.3, 0.025, 0.1), -0.25)
    assert scene.pose("BOX") == pytest.approx((0.3, 0.025, 0.1, -0.25))
    (box,) = world.blocks
    assert (box.x_m, box.y_m, box.yaw_rad) == pytest.approx((-0.1, -0.3, -0.25))
    # The ground slot sits at (0.03, 0, 0.0003) on the robot (x forward, y left, z up).
    x, y = -0.2 + 0.03 * math.cos(1.0), 0.1 + 0.03 * math.sin(1.0)
    assert device_values(world, "gps") == pytest.approx((-y, 0.0003, -x))
    # Webots before R2022a: north is +x, the robot's axes x right, y up, z back. Turned
    # 1 rad about +y from facing -z, the robot has north behind it, to its right.
    assert device_values(world, "compass") == pytest.approx((math.cos(1.0), 0.0, math.sin(1.0)))
