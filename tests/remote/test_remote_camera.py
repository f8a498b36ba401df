"""The robot's camera through ``ego serve``: raw frames for the client's Camera, JPEG, PNG."""

from __future__ import annotations

import cv2
import numpy as np
import pytest
from helpers import wait_until
from remote_helpers import ConnectFactory, FakeCamera, ServeFactory

from ego.backends.remote.channel import RemoteFrameSource
from ego.camera import Camera
from ego.errors import CameraError, RemoteError
from ego.net.frames import MAX_PAYLOAD
from firmware_sim.camera import SimulatedSource


def _source(connect: ConnectFactory, url: str, **options: object) -> RemoteFrameSource:
    return RemoteFrameSource(connect(url, **options))


def test_frames_controls_and_close_reach_the_robots_camera(
    serve: ServeFactory, connect: ConnectFactory, kind: str
) -> None:
    camera = FakeCamera()
    served = serve(kinds=(kind,), frame_source=camera)
    source = _source(connect, served.url)
    assert source.open(160, 120, "RGB565") == (160, 120, 320)
    assert camera.opened == (160, 120, "RGB565")
    assert source.read_frame() == camera.expected(1)  # 38,400 bytes: sliced over UDP
    assert source.read_frame() == camera.expected(2)
    assert source.set_control("brightness", 300) == 255  # what the camera took
    assert source.set_fov_rad(0.5) == 0.5  # fixed optics: reported as asked
    source.close()
    source.close()
    assert camera.closed == 1


def test_remote_image_is_the_image_a_local_camera_sees(
    serve: ServeFactory, connect: ConnectFactory, kind: str
) -> None:
    served = serve(kinds=(kind,), sim_camera=True)
    with Camera(source=_source(connect, served.url), width=160, height=120) as remote:
        image = remote.capture().copy()  # converted and rotated on the client
        assert remote.fov_rad == pytest.approx(0.84)
        remote.fov_rad = 0.6  # the emulated camera zooms
    with Camera(
        source=SimulatedSource(served.emu.world, fov_rad=0.84), width=160, height=120
    ) as local:
        assert np.array_equal(image, local.capture())


def test_png_is_the_frame_and_jpeg_shrinks_with_quality(
    serve: ServeFactory, connect: ConnectFactory, kind: str
) -> None:
    served = serve(kinds=(kind,), sim_camera=True)
    source = _source(connect, served.url)
    source.open(160, 120, "RGB565")
    png = cv2.imdecode(np.frombuffer(source.fetch_encoded("png"), np.uint8), cv2.IMREAD_COLOR)
    with Camera(source=SimulatedSource(served.emu.world), width=160, height=120) as local:
        upright = local.capture()
    assert np.array_equal(png[:, :, ::-1], upright)  # lossless, rotated like the Camera
    small, large = source.fetch_encoded("jpeg", 10), source.fetch_encoded("jpeg", 95)
    assert small[:2] == large[:2] == b"\xff\xd8"
    assert len(small) < len(large)
    jpeg = cv2.imdecode(np.frombuffer(large, np.uint8), cv2.IMREAD_COLOR)
    assert jpeg.shape == (120, 160, 3)
    assert np.abs(jpeg[:, :, ::-1].astype(int) - upright).mean() < 8


def test_server_without_a_camera_says_so(serve: ServeFactory, connect: ConnectFactory) -> None:
    source = _source(connect, serve().url)
    with pytest.raises(CameraError, match="no camera"):
        source.open(160, 120, "RGB565")


def test_frame_before_open_is_refused(serve: ServeFactory, connect: ConnectFactory) -> None:
    served = serve(frame_source=FakeCamera())
    source = _source(connect, served.url)
    with pytest.raises(CameraError, match="not open"):
        source.read_frame()


def test_frame_over_the_size_limit_is_refused(serve: ServeFactory, connect: ConnectFactory) -> None:
    served = serve(frame_source=FakeCamera(frame_bytes=MAX_PAYLOAD + 1))
    source = _source(connect, served.url)
    source.open(640, 480, "RGB565")
    with pytest.raises(RemoteError, match="exceeds"):
        source.read_frame()
    assert source.set_control("contrast", 64) == 64  # the session goes on


def test_silent_client_has_its_camera_closed(serve: ServeFactory, connect: ConnectFactory) -> None:
    camera = FakeCamera()
    served = serve(frame_source=camera, deadline_s=0.2)
    source = _source(connect, served.url, heartbeat=False)
    source.open(64, 48, "RGB565")
    assert wait_until(lambda: camera.closed == 1)


def test_local_transport_has_no_remote_camera(link: object) -> None:
    transport = link
    with pytest.raises(CameraError, match="not a remote robot"):
        RemoteFrameSource(transport)
