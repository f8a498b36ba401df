"""The emulated camera: the world seen from the robot, delivered upside down as RGB565."""

from __future__ import annotations

import numpy as np
import pytest
from camera_fakes import StandInBlock, StandInPose, StandInWorld

from ego.camera import Camera, PixelFormat, rgb565_to_rgb888
from firmware_sim.camera import (
    BACKGROUND_RGB,
    FLOOR_RGB,
    LAMP_RGB,
    SimulatedSource,
    rgb888_to_rgb565,
)

RED = (200, 30, 30)
W, H = 64, 48


def near(pixel: np.ndarray, rgb: tuple[int, int, int], tolerance: int = 8) -> bool:
    return bool(np.abs(pixel.astype(int) - np.array(rgb)).max() <= tolerance)


def reddish(pixel: np.ndarray) -> bool:
    """Red whichever face (the renderer shades faces turned along y a little darker)."""
    r, g, b = (int(c) for c in pixel)
    return r > 120 and g < 60 and b < 60


def raw_frame(world, width: int = W, height: int = H, fmt=PixelFormat.RGB565) -> bytes:
    source = SimulatedSource(world)
    granted = source.open(width, height, fmt)
    assert granted == (width, height, 2 * width)
    return source.read_frame()


def test_facing_a_coloured_block_shows_its_colour_in_the_centre(world: StandInWorld):
    world.blocks.append(StandInBlock(0.15, 0.0, 0.03, RED))
    upright = rgb565_to_rgb888(raw_frame(world), W, H)  # the camera's default rotation, 180
    assert near(upright[H // 2, W // 2], RED)
    assert near(upright[H // 2 + 10, W // 2], RED)  # the block's face reaches below the horizon


def test_raw_frame_is_upside_down_like_the_real_mounting(world: StandInWorld):
    raw = raw_frame(world)
    as_delivered = rgb565_to_rgb888(raw, W, H, rotation=0)
    upright = rgb565_to_rgb888(raw, W, H, rotation=180)
    assert near(upright[-1, 0], FLOOR_RGB) and near(upright[0, 0], BACKGROUND_RGB)
    assert near(as_delivered[0, 0], FLOOR_RGB) and near(as_delivered[-1, 0], BACKGROUND_RGB)


@pytest.mark.parametrize(("y_m", "side"), [(0.1, "left"), (-0.1, "right")])
def test_a_block_on_the_robots_left_appears_on_the_images_left(world, y_m, side):
    world.blocks.append(StandInBlock(0.3, y_m, 0.03, RED))
    upright = rgb565_to_rgb888(raw_frame(world), W, H)
    red_columns = np.flatnonzero([near(upright[H // 2, c], RED) for c in range(W)])
    assert red_columns.size > 0
    assert (red_columns.mean() < W / 2) == (side == "left")


def test_turning_brings_a_block_into_view(world: StandInWorld):
    world.blocks.append(StandInBlock(0.0, 0.25, 0.03, RED))  # on the left, out of view
    before = rgb565_to_rgb888(raw_frame(world), W, H)
    world.pose = StandInPose(0.0, 0.0, np.pi / 2)  # turn left, to face +y
    after = rgb565_to_rgb888(raw_frame(world), W, H)
    assert not reddish(before[H // 2, W // 2]) and reddish(after[H // 2, W // 2])


def test_walls_fill_the_view_at_the_horizon_with_their_colour(world: StandInWorld):
    upright = rgb565_to_rgb888(raw_frame(world), W, H)
    assert near(upright[H // 2 - 2, W // 2], world.arena.wall_rgb)


def test_the_lamp_is_seen_as_a_lit_post(world: StandInWorld):
    world.lamp.x_m, world.lamp.y_m = 0.25, 0.0
    upright = rgb565_to_rgb888(raw_frame(world), W, H)
    assert near(upright[H // 2 - 5, W // 2], LAMP_RGB)


def test_a_nearer_block_hides_a_farther_one_whatever_the_list_order(world: StandInWorld):
    blue = (30, 60, 200)
    world.blocks += [StandInBlock(0.12, 0.0, 0.02, RED), StandInBlock(0.3, 0.0, 0.08, blue)]
    upright = rgb565_to_rgb888(raw_frame(world), W, H)
    middle = upright[H // 2]
    red = [c for c in range(W) if near(middle[c], RED)]
    blue_columns = [c for c in range(W) if near(middle[c], blue)]
    assert W // 2 in red and blue_columns  # the far, wider block shows on both sides only
    assert not set(red) & set(blue_columns)
    assert min(blue_columns) < min(red) and max(blue_columns) > max(red)


def test_the_emulator_world_renders_its_floor_and_blocks():
    world_module = pytest.importorskip("firmware_sim.world")
    world = world_module.World(
        noise=False,
        blocks=[world_module.Block(0.2, 0.0, 0.04, (30, 160, 40))],
        start=world_module.Pose(0.0, 0.0, 0.0),
    )
    upright = rgb565_to_rgb888(raw_frame(world), W, H)
    assert near(upright[H // 2, W // 2], (30, 160, 40))
    floor = world.floor_rgb_at(np.array([0.05]), np.array([0.0]))[0]
    assert near(upright[-1, W // 2], tuple(int(c) for c in floor))


def test_big_endian_frames_are_the_little_endian_ones_byte_swapped(world: StandInWorld):
    world.blocks.append(StandInBlock(0.2, 0.05, 0.03, RED))
    little = np.frombuffer(raw_frame(world), "<u2")
    big = np.frombuffer(raw_frame(world, fmt=PixelFormat.RGB565_BE), ">u2")
    assert np.array_equal(little, big)


def test_sizes_beyond_the_sensor_are_clamped_and_yuyv_is_refused(world: StandInWorld):
    source = SimulatedSource(world)
    assert source.open(1000, 10, PixelFormat.RGB565) == (640, 32, 1280)
    with pytest.raises(ValueError, match="RGB565 only"):
        source.open(64, 48, PixelFormat.YUYV)


def test_rgb565_quantisation_rounds_each_channel_to_its_nearest_level():
    rgb = np.array([[[255, 255, 255], [0, 0, 0], [8, 4, 8], [4, 2, 3]]], dtype=np.uint8)
    assert rgb888_to_rgb565(rgb).tolist() == [[0xFFFF, 0x0000, 0x0821, 0x0000]]


def test_camera_on_the_emulator_zooms_with_its_field_of_view(world: StandInWorld):
    world.blocks.append(StandInBlock(0.3, 0.0, 0.03, RED))
    with Camera(source=SimulatedSource(world), width=W, height=H) as camera:
        camera.enable(64)
        camera.update(0)
        wide = sum(near(p, RED) for p in camera.image[H // 2])
        camera.fov_rad = 0.4
        camera.update(64)
        narrow = sum(near(p, RED) for p in camera.image[H // 2])
    assert narrow > 1.5 * wide > 0
