"""On a machine with a real video device (the Overo): capture one frame through V4L2."""

from __future__ import annotations

import glob

import pytest

from ego.camera import Camera, V4L2Source

DEVICES = sorted(glob.glob("/dev/video*"))

pytestmark = [
    pytest.mark.hardware,
    pytest.mark.skipif(not DEVICES, reason="no /dev/video* device on this machine"),
]


def test_real_device_delivers_a_converted_frame():
    with Camera(source=V4L2Source(DEVICES[0]), width=160, height=120) as camera:
        camera.enable(64)
        assert camera.update(0)
        assert camera.image.shape == (camera.height, camera.width, 3)
        assert camera.image.std() > 0  # not a blank buffer
