"""The camera over WiFi: 160x120 RGB565 big-endian frames (ESP:socket_e-puck2.c:206-226)
through ego's exact converters, asked of the robot only while the camera reads them."""

from __future__ import annotations

import time

import numpy as np
from wifi_relay import Relay

import ego
from ego.backends.epuck2.wifi_packets import IMAGE_SIZE, image_to_rgb888
from ego.camera.convert import rgb565_to_rgb888
from firmware_sim.epuck2 import Epuck2Emulator
from firmware_sim.epuck2.camera import frame_rgb565_be


def test_the_big_endian_image_s_colours(wifi: Epuck2Emulator, url: str) -> None:
    with ego.Robot(url) as robot:
        robot.camera.enable(16)
        robot.step(16)
        image = np.array(robot.camera.image)
    # The robot stood still: the frame the radio sent is the one its world renders.
    raw = frame_rgb565_be(wifi.world, 160, 120, 640)
    assert image.shape == (120, 160, 3)
    assert np.array_equal(image, image_to_rgb888(raw))
    # Read as little-endian, the same bytes give other colours: the byte order matters.
    assert not np.array_equal(image, rgb565_to_rgb888(raw, 160, 120, 0, byteorder="little"))
    assert len(np.unique(image.reshape(-1, 3), axis=0)) > 3  # a scene, not a flat field


def _received_over(relay: Relay, robot: ego.Robot, seconds: float) -> int:
    before = relay.down_bytes
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        robot.step(32)
    return relay.down_bytes - before


def test_the_image_is_asked_only_while_the_camera_reads(relay: Relay, relay_url: str) -> None:
    with ego.Robot(relay_url) as robot:
        robot.proximity.enable(32)
        assert _received_over(relay, robot, 0.5) < IMAGE_SIZE  # sensor packets only
        robot.camera.enable(32)
        frames = robot.camera.frame_count
        with_camera = _received_over(relay, robot, 0.5)
        frames = robot.camera.frame_count - frames
        assert frames >= 3
        assert with_camera >= frames * (IMAGE_SIZE + 1)
        robot.camera.disable()  # it reads no more frames: within a second the stream stops
        _received_over(relay, robot, 1.2)
        assert _received_over(relay, robot, 0.5) < IMAGE_SIZE
        robot.camera.enable(32)
        assert _received_over(relay, robot, 0.5) >= IMAGE_SIZE
        robot.camera.close()  # no reader left: the robot stops sending frames
        time.sleep(0.1)
        assert _received_over(relay, robot, 0.5) < IMAGE_SIZE


def test_frames_come_again_after_a_drop(relay: Relay, relay_url: str) -> None:
    with ego.Robot(relay_url) as robot:
        robot.camera.enable(32)
        robot.step(32)
        frames = robot.camera.frame_count
        relay.cut()
        time.sleep(0.1)
        for _ in range(3):
            robot.step(32)
        assert robot.camera.frame_count == frames + 3
        assert robot.channel.stats.reconnects == 1
