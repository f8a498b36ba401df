"""The e-puck2's camera as asercom and the radio deliver it: the world rendered by
firmware_sim.camera, packed as RGB565 big-endian (the sensor's byte order, high byte
first: RRRRRGGG GGGBBBBB), upright [orientation inferred]."""

from __future__ import annotations

from firmware_sim.camera import DEFAULT_FOV_RAD, render_rgb888, rgb888_to_rgb565
from firmware_sim.world import World

__all__ = ["SENSOR_WIDTH", "frame_rgb565_be"]

#: MAIN:src/epuck1x/camera/fast_2_timer/e_poxxxx.h:22-23, ARRAY_WIDTH x ARRAY_HEIGHT.
SENSOR_WIDTH = 640
SENSOR_HEIGHT = 480


def frame_rgb565_be(world: World, width: int, height: int, window_width: int) -> bytes:
    """A ``width`` x ``height`` frame of a ``window_width``-pixel-wide window of the
    640-pixel sensor (the field of view shrinks with the window)."""
    fov = DEFAULT_FOV_RAD * min(1.0, window_width / SENSOR_WIDTH)
    codes = rgb888_to_rgb565(render_rgb888(world, width, height, fov_rad=fov))
    return codes.astype(">u2").tobytes()
