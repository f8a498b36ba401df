"""Webots world files (.wbt) drive the emulator: the arena, the boxes, the e-puck's pose and
camera size, and the floor texture, read from a small world written for the test."""

from __future__ import annotations

import logging
import math
import re
import subprocess
from pathlib import Path

import numpy as np
import pytest
from helpers import ego_command
from PIL import Image

from firmware_sim.floor import ImageFloor, Plain
from firmware_sim.wbt import parse_wbt
from firmware_sim.worlds import load_world

WORLD = """#VRML_SIM R2023b utf8
# A line-following lab: a half-black floor, two boxes and the e-puck.
EXTERNPROTO "https://raw.githubusercontent.com/cyberbotics/webots/R2023b/projects/objects/floors/protos/RectangleArena.proto"
IMPORTABLE EXTERNPROTO "https://example.org/WoodenBox.proto"
WorldInfo { basicTimeStep 32 }
Viewpoint { orientation -0.5 0.5 0.7 2.0 position 0 0 2 }
TexturedBackground { }
RectangleArena {
  floorSize 1.2 0.6
  floorTileSize 1.2 0.6
  wallHeight 0.07
  floorAppearance PBRAppearance {
    baseColorMap ImageTexture { url [ "textures/half.png" ] }
    roughness 1
  }
}
DEF CRATE WoodenBox {
  translation 0.3 0.1 0.05
  rotation 0 0 1 0.7854
  size 0.1 0.05 0.1
}
Solid {
  translation -0.3 -0.1 0.025
  children [
    Shape {
      appearance PBRAppearance { baseColor 1 0 0 metalness 0 }
      geometry Box { size 0.06 0.04 0.05 }
    }
  ]
  name "red box"
  boundingObject Box { size 0.06 0.04 0.05 }
}
E-puck {
  translation 0.1 -0.2 0
  rotation 0 0 1 1.5708
  controller "my_controller"
  camera_width 80
  camera_height 60
}
Robot { name "a robot ego does not model" }
"""


@pytest.fixture
def world_file(tmp_path: Path) -> Path:
    """The world above, beside its texture: black on the image's left half (x < 0)."""
    (tmp_path / "textures").mkdir()
    image = np.full((60, 120, 3), 255, np.uint8)
    image[:, :60] = 0
    Image.fromarray(image).save(tmp_path / "textures" / "half.png")
    path = tmp_path / "lab.wbt"
    path.write_text(WORLD)
    return path


def test_the_parser_keeps_nodes_fields_and_def_names() -> None:
    version, nodes = parse_wbt(WORLD)
    assert version == "R2023b"
    types = [node.type for node in nodes]
    assert types == ["WorldInfo", "Viewpoint", "TexturedBackground", "RectangleArena",
                     "WoodenBox", "Solid", "E-puck", "Robot"]  # fmt: skip
    crate = nodes[4]
    assert crate.name == "CRATE"
    assert crate.fields["rotation"] == [0, 0, 1, 0.7854]
    assert nodes[6].fields["controller"] == ["my_controller"]
    assert nodes[5].fields["children"][0].fields["geometry"].type == "Box"


def test_the_arena_boxes_pose_and_camera_come_from_the_file(world_file: Path) -> None:
    world = load_world(world_file, seed=1)
    assert world.arena.half_extents == pytest.approx((0.6, 0.3))
    assert world.arena.wall_height_m == pytest.approx(0.07)
    crate, red = world.blocks
    assert (crate.x_m, crate.y_m, crate.yaw_rad) == pytest.approx((0.3, 0.1, 0.7854))
    assert crate.half_extents == pytest.approx((0.05, 0.025))
    assert crate.height_m == pytest.approx(0.1)
    assert red.rgb == (255, 0, 0)
    assert red.half_extents == pytest.approx((0.03, 0.02))
    pose = world.snapshot()
    assert (pose.x_m, pose.y_m, pose.theta_rad) == pytest.approx((0.1, -0.2, 1.5708))
    assert world.camera_size == (80, 60)


def test_the_floor_texture_is_what_the_ground_sensors_read(world_file: Path) -> None:
    world = load_world(world_file, seed=1)
    assert isinstance(world.floor_pattern, ImageFloor)
    assert world.floor() == pytest.approx([1000, 1000, 1000], abs=30)  # x = 0.1: white
    world.place(type(world.snapshot())(-0.2, -0.2, 0.0))
    assert max(world.floor()) < 350  # x = -0.2: the black half


def test_a_rotated_box_blocks_rays_along_its_turned_faces(world_file: Path) -> None:
    world = load_world(world_file, seed=1)
    # Along the crate's centre line from 20 cm to its -x: turned 45 degrees, the box is met
    # on its narrow side at 2.5 cm / cos 45 from its centre (unturned: 5 cm).
    distance = world.ray_distance(0.1, 0.1, 0.0)
    assert distance == pytest.approx(0.2 - 0.025 / math.cos(0.7854), abs=1e-4)
    # Straight down onto it from above (+y): the same narrow half width, turned.
    assert world.ray_distance(0.3, 0.3, -math.pi / 2) == pytest.approx(
        0.2 - 0.025 / math.cos(0.7854), abs=1e-4
    )


def test_what_the_emulator_does_not_model_is_skipped_with_a_note(
    world_file: Path, caplog: pytest.LogCaptureFixture
) -> None:
    with caplog.at_level(logging.INFO, logger="firmware_sim.worlds"):
        load_world(world_file)
    warnings = [r.getMessage() for r in caplog.records if r.levelno == logging.WARNING]
    infos = [r.getMessage() for r in caplog.records if r.levelno == logging.INFO]
    assert warnings == ["lab.wbt: skipped 1 Robot"]
    assert "lab.wbt: skipped 1 Viewpoint" in infos


def test_a_world_without_texture_has_a_plain_floor(tmp_path: Path) -> None:
    path = tmp_path / "plain.wbt"
    path.write_text("#VRML_SIM R2023b utf8\nRectangleArena { }\n")
    world = load_world(path)
    assert isinstance(world.floor_pattern, Plain)
    assert world.arena.half_extents == (0.5, 0.5)  # Webots' default floorSize 1 1
    assert world.blocks == []


@pytest.mark.parametrize(
    ("text", "error"),
    [
        (
            '#VRML_SIM R2021b utf8\nWorldInfo { coordinateSystem "ENU" }\n',
            "R2021b world declared ENU keeps its objects in the old axes.*R2022a",
        ),
        (
            "#VRML_SIM R2023b utf8\nWoodenBox { rotation 1 0 0 0.3 }\n",
            "WoodenBox.rotation 1 0 0 0.3 stands the box on an edge or a corner",
        ),
        ("#VRML_SIM R2023b utf8\nRectangleArena { floorSize 1 }\n", "floorSize must be 2"),
        (
            '#VRML_SIM R2023b utf8\nWorldInfo { coordinateSystem "EUN" }\n',
            "WorldInfo.coordinateSystem 'EUN': the emulator reads ENU .* and NUE",
        ),
        (
            "#VRML_SIM R2021b utf8\nRectangleArena { floorAppearance PBRAppearance {"
            ' baseColorMap ImageTexture { url [ "floor.png" ] } } }\n',
            "RectangleArena.floorAppearance: a floor image in an NUE world is not modelled",
        ),
        (
            "#VRML_SIM R2023b utf8\nRectangleArena { rotation 1 0 0 0.3 }\n",
            r"RectangleArena.rotation is rotated about \(1.0, 0.0, 0.0\), not the vertical",
        ),
        (
            '#VRML_SIM R2023b utf8\nE-puck { turretSlot [ GPS { name "gps2" } ] }\n',
            "E-puck.turretSlot GPS.name \\['gps2'\\]: the emulator serves a GPS named 'gps'",
        ),
        (
            "#VRML_SIM R2023b utf8\nE-puck { groundSensorsSlot [ Compass {"
            " rotation 0 0 1 1 } ] }\n",
            "E-puck.groundSensorsSlot Compass.rotation 0 0 1 1: a device turned on the robot",
        ),
        ("#VRML_SIM R2023b utf8\nRectangleArena { floorSize 0 1 }\n", "must be positive"),
        ("#VRML_SIM R2023b utf8\nRectangleArena {\n", "ends inside a node"),
        ("#VRML_SIM R2023b utf8\nE-puck { camera_width 52.5 }\n", "whole pixels"),
        ("#VRML_SIM R2023b utf8\nSolid { children [ USE NOPE ] }\n", "USE NOPE before"),
        (
            "#VRML_SIM R2023b utf8\nRectangleArena { floorAppearance PBRAppearance {"
            ' baseColorMap ImageTexture { url [ "missing.png" ] } } }\n',
            "missing.png",
        ),
    ],
)
def test_a_world_ego_cannot_model_is_refused_naming_the_file(
    tmp_path: Path, text: str, error: str
) -> None:
    path = tmp_path / "bad.wbt"
    path.write_text(text)
    with pytest.raises(ValueError, match=error) as info:
        load_world(path)
    assert str(path) in str(info.value)


def test_a_webots_controller_runs_in_the_wbt_world_with_its_camera_size(
    world_file: Path, tmp_path: Path
) -> None:
    controller = tmp_path / "probe.py"
    controller.write_text(
        "from controller import Robot\n"
        "robot = Robot()\n"
        "camera = robot.getDevice('camera'); camera.enable(64)\n"
        "ground = [robot.getDevice(f'gs{i}') for i in range(3)]\n"
        "for sensor in ground: sensor.enable(64)\n"
        "robot.step(64)\n"
        "print(camera.getWidth(), camera.getHeight(), len(camera.getImage()))\n"
        "print(*[round(sensor.getValue()) for sensor in ground])\n"
    )
    result = subprocess.run(
        [*ego_command(), "run", "--port", "sim", "--world", str(world_file), str(controller)],
        capture_output=True, text=True, cwd=tmp_path, timeout=60,
    )  # fmt: skip
    assert result.returncode == 0, result.stderr
    size, ground = result.stdout.strip().splitlines()
    assert size == "80 60 19200"  # the E-puck node's camera_width/height, BGRA
    assert min(map(int, ground.split())) > 900  # the white half of the texture


def test_the_camera_sees_the_turned_box_where_the_rays_meet_it(world_file: Path) -> None:
    from firmware_sim.camera import render_rgb888

    world = load_world(world_file, seed=1)
    pose = type(world.snapshot())
    # Facing the crate along its centre line, then facing past it (turned 90 degrees).
    facing = render_rgb888(world, 80, 60, pose=pose(0.1, 0.1, 0.0))
    past = render_rgb888(world, 80, 60, pose=pose(0.1, 0.1, math.pi / 2))
    crate = np.array(world.blocks[0].rgb, np.int64)
    centre = facing[28:32, 38:42].reshape(-1, 3).astype(np.int64)
    # Lit faces keep the colour, faces turned along y are shaded 0.8: either way, its hue.
    assert all(np.allclose(px, crate, atol=2) or np.allclose(px, crate * 0.8, atol=2)
               for px in centre)  # fmt: skip
    assert not np.any(np.all(np.abs(past.astype(np.int64) - crate) <= 2, axis=-1))


#: Boxes as Webots' world converter writes them from a y-up world: lying on a face, the
#: rotation swaps the box's y and z (its 0.2 m side now lies along the floor's y).
ON_A_FACE = """#VRML_SIM R2023b utf8
RectangleArena { floorSize 1 1 }
DEF LYING WoodenBox {
  translation 0.2 0 0.025
  rotation 1 0 0 1.5708
  size 0.1 0.05 0.2
}
DEF TURNED_AND_LYING WoodenBox {
  translation -0.2 0.2 0.05
  rotation 0.5773 0.5773 0.5773 2.0944
  size 0.1 0.2 0.05
}
E-puck { }
"""


def test_boxes_lying_on_a_face_stand_on_the_floor_with_their_sides_swapped(
    tmp_path: Path,
) -> None:
    path = tmp_path / "converted.wbt"
    path.write_text(ON_A_FACE)
    blocks = {b.name: b for b in load_world(str(path)).blocks}
    lying = blocks["LYING"]
    # About x by 90 degrees: the box's z (0.2) now runs along the floor's y, its y (0.05)
    # is its height; its x stays the floor's x.
    assert (lying.half_size_m * 2, lying.half_y_m * 2, lying.height_m) == pytest.approx(
        (0.1, 0.2, 0.05)
    )
    assert math.cos(lying.yaw_rad) == pytest.approx(1.0)
    # 120 degrees about (1, 1, 1): x -> y, y -> z, z -> x. Its height is its y (0.2) and
    # its x (0.1) runs along the floor's y: the footprint turned a quarter turn.
    turned = blocks["TURNED_AND_LYING"]
    assert (turned.half_size_m * 2, turned.half_y_m * 2, turned.height_m) == pytest.approx(
        (0.1, 0.05, 0.2), abs=1e-3
    )
    assert turned.yaw_rad == pytest.approx(math.pi / 2, abs=1e-3)


def test_a_box_standing_on_an_edge_is_refused_naming_its_rotation(tmp_path: Path) -> None:
    path = tmp_path / "edge.wbt"
    path.write_text(ON_A_FACE.replace("rotation 1 0 0 1.5708", "rotation 1 0 0 0.7854"))
    refused = re.escape("WoodenBox LYING.rotation 1 0 0 0.7854 stands the box on an edge")
    with pytest.raises(ValueError, match=refused):
        load_world(str(path))
