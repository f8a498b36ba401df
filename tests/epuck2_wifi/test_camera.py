"""The camera over WiFi: 160x120 RGB565 big-endian frames (ESP:socket_e-puck2.c:206-226)
through ego's exact converters, asked of the robot only while the camera reads them."""

from __future__ import annotations

import time

import numpy as np
from helpers import wait_until
from wifi_relay import Relay

import ego
from ego.backends.epuck2.channel import IMAGE_IDLE_S
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


def _received_over(relay: Relay, robot: ego.Robot, steps: int = 15) -> int:
    """The bytes the robot sent over ``steps`` of the controller's steps: each step's
    command is a chance for the radio to send a frame, however slow the machine."""
    before = relay.down_bytes
    for _ in range(steps):
        robot.step(32)
    return relay.down_bytes - before


def _idle_past_the_image_deadline(robot: ego.Robot) -> None:
    """Step until the camera has not read for IMAGE_IDLE_S and more, on the clock ego's
    deadline reads (time.monotonic): a timeout, so a time, not a count."""
    end = time.monotonic() + IMAGE_IDLE_S + 0.2
    while time.monotonic() < end:
        robot.step(32)


def _drain(robot: ego.Robot) -> None:
    """Step until the robot has sent three sensor packets after the last command: a
    frame on its way before them has arrived (one TCP stream, in order)."""
    heard = robot.channel.heard
    seen = heard.sensors_seq
    while robot.channel.heard.sensors_seq < seen + 3:
        assert robot.step(32) != -1


def test_the_image_is_asked_only_while_the_camera_reads(relay: Relay, relay_url: str) -> None:
    with ego.Robot(relay_url) as robot:
        robot.proximity.enable(32)
        assert _received_over(relay, robot) < IMAGE_SIZE  # sensor packets only
        robot.camera.enable(32)
        frames = robot.camera.frame_count
        with_camera = _received_over(relay, robot)
        frames = robot.camera.frame_count - frames
        assert frames >= 3
        assert with_camera >= frames * (IMAGE_SIZE + 1)
        robot.camera.disable()  # it reads no more frames: within a second the stream stops
        _idle_past_the_image_deadline(robot)
        _drain(robot)
        assert _received_over(relay, robot) < IMAGE_SIZE
        robot.camera.enable(32)
        assert _received_over(relay, robot) >= IMAGE_SIZE
        robot.camera.close()  # no reader left: the robot stops sending frames
        _drain(robot)  # a frame on its way as the camera closed
        assert _received_over(relay, robot) < IMAGE_SIZE


def test_frames_come_again_after_a_drop(relay: Relay, relay_url: str) -> None:
    with ego.Robot(relay_url) as robot:
        robot.camera.enable(32)
        robot.step(32)
        frames = robot.camera.frame_count
        relay.cut()
        assert wait_until(lambda: robot.channel.heard.lost is not None)
        for _ in range(3):
            robot.step(32)
        assert robot.camera.frame_count == frames + 3
        assert robot.channel.stats.reconnects == 1
