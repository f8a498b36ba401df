"""Replaying raw frames recorded to files."""

from __future__ import annotations

import errno

import numpy as np
import pytest
from camera_fakes import pattern_codes, pattern_frame

from ego.camera import Camera, FileReplaySource, PixelFormat
from ego.errors import CameraCaptureError


@pytest.fixture
def recording(tmp_path):
    """Two files: frames 0 and 1 back to back in the first, frame 2 in the second."""
    first, second = tmp_path / "run1.raw", tmp_path / "run2.raw"
    first.write_bytes(pattern_frame(0, 32, 32, 64) + pattern_frame(1, 32, 32, 64))
    second.write_bytes(pattern_frame(2, 32, 32, 64))
    return [first, second]


def test_frames_come_back_in_order_across_files_and_loop(recording):
    source = FileReplaySource(recording, 32, 32)
    assert source.open(32, 32, PixelFormat.RGB565) == (32, 32, 64)
    frames = [source.read_frame() for _ in range(4)]
    assert frames == [pattern_frame(i % 3, 32, 32, 64) for i in range(4)]
    source.close()


def test_without_loop_the_end_of_the_replay_is_an_error(recording):
    source = FileReplaySource(recording[1], 32, 32, loop=False)
    source.open(32, 32, PixelFormat.RGB565)
    source.read_frame()
    with pytest.raises(CameraCaptureError, match="replay of 1 file") as caught:
        source.read_frame()
    assert caught.value.errno == errno.ENODATA


def test_the_recorded_size_is_granted_whatever_was_asked(recording):
    source = FileReplaySource(recording, 32, 32)
    assert source.open(640, 480, PixelFormat.RGB565)[:2] == (32, 32)


def test_a_file_of_partial_frames_is_refused_naming_it(tmp_path):
    path = tmp_path / "cut.raw"
    path.write_bytes(bytes(100))
    with pytest.raises(CameraCaptureError, match=r"cut.raw holds 100 bytes, not whole 2048"):
        FileReplaySource(path, 32, 32).open(32, 32, PixelFormat.RGB565)


def test_another_pixel_format_is_refused(recording):
    with pytest.raises(CameraCaptureError, match="recorded frames are RGB565"):
        FileReplaySource(recording, 32, 32).open(32, 32, PixelFormat.YUYV)


def test_camera_replays_recorded_frames_upright(recording, thesis_table):
    with Camera(source=FileReplaySource(recording, 32, 32), width=32, height=32) as camera:
        camera.enable(10)
        for t in (0, 10, 20):
            camera.update(t)
        assert np.array_equal(camera.image, thesis_table[pattern_codes(2, 32, 32)][::-1, ::-1])
