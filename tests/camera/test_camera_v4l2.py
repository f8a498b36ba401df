"""V4L2 capture against an in-process fake device that decodes the real ioctls and structs."""

from __future__ import annotations

import ctypes
import errno

import numpy as np
import pytest
from camera_fakes import (
    CID_SATURATION,
    REQUESTS,
    WORD64,
    FakeVideoDevice,
    pattern_codes,
    pattern_frame,
)

from ego.camera import (
    Camera,
    CameraTimeoutError,
    PixelFormat,
    UnsupportedControlError,
    V4L2Source,
    rgb565_to_rgb888,
    videodev2,
)
from ego.errors import CameraCaptureError, CameraError


def source_on(device: FakeVideoDevice, **kwargs) -> V4L2Source:
    return V4L2Source(device.path, syscalls=device, **kwargs)


@pytest.fixture
def source(device: FakeVideoDevice):
    src = source_on(device, timeout_s=0.2)
    yield src
    src.close()
    assert device.leaks() == []


def test_request_numbers_match_the_kernel_header():
    ours = {name: getattr(videodev2, f"VIDIOC_{name}") for name in REQUESTS}
    assert {k: hex(v) for k, v in ours.items()} == {k: hex(v) for k, v in REQUESTS.items()}


def test_struct_sizes_match_the_kernel_abi():
    sizes = {
        videodev2.v4l2_capability: 104,
        videodev2.v4l2_format: 208 if WORD64 else 204,
        videodev2.v4l2_requestbuffers: 20,
        videodev2.v4l2_buffer: 88 if WORD64 else 68,
        videodev2.v4l2_control: 8,
        videodev2.v4l2_queryctrl: 68,
    }
    assert {s.__name__: ctypes.sizeof(s) for s in sizes} == {
        s.__name__: n for s, n in sizes.items()
    }


def test_open_negotiates_streams_and_delivers_the_device_frame(device, source):
    granted = source.open(64, 48, PixelFormat.RGB565)
    assert granted == (64, 48, 128) == device.granted
    assert source.driver == "fakecam" and source.card == "Fake e-puck camera"
    assert device.streaming and len(device.buffers) == 4
    assert device.calls[:3] == ["open", "QUERYCAP", "S_FMT"]
    assert bytes(source.read_frame()) == pattern_frame(0, 64, 48, 128)
    assert bytes(source.read_frame()) == pattern_frame(1, 64, 48, 128)


def test_padded_stride_is_reported_and_honoured(device, source, thesis_table):
    device.stride_align = 64  # 100 pixels = 200 bytes, padded to 256
    granted = source.open(100, 40, PixelFormat.RGB565)
    assert granted.stride_bytes == 256
    raw = source.read_frame()
    assert len(raw) == 256 * 40
    rgb = rgb565_to_rgb888(raw, 100, 40, 180, stride_bytes=granted.stride_bytes)
    assert np.array_equal(rgb, thesis_table[pattern_codes(0, 100, 40)][::-1, ::-1])


def test_size_adjusted_by_the_driver_is_reported(device, source):
    device.width_align, device.height_align = 16, 4
    assert source.open(100, 75, PixelFormat.RGB565)[:2] == (96, 72)
    assert source.open(700, 10, PixelFormat.RGB565)[:2] == (640, 32)


def test_fewer_buffers_than_asked_still_stream(device):
    device.max_buffers = 2
    src = source_on(device, buffer_count=5)
    src.open(32, 32, PixelFormat.RGB565)
    assert len(device.buffers) == 2 and len(device.maps) == 2
    frames = [bytes(src.read_frame()) for _ in range(5)]
    assert frames == [pattern_frame(i, 32, 32, 64) for i in range(5)]
    src.close()
    assert device.leaks() == []


def test_no_buffers_granted_is_an_error_and_leaves_nothing_open(device, source):
    device.max_buffers = 0
    with pytest.raises(CameraCaptureError, match="no capture buffers") as caught:
        source.open(32, 32, PixelFormat.RGB565)
    assert caught.value.errno == errno.ENOMEM
    assert device.leaks() == []


def test_a_format_the_device_substitutes_is_refused(device, source):
    device.formats = ("YUYV",)
    with pytest.raises(CameraCaptureError, match="cannot deliver RGB565; it offers 'YUYV'"):
        source.open(64, 48, PixelFormat.RGB565)
    assert device.leaks() == []


def test_yuyv_is_negotiated_with_its_fourcc(device, source):
    source.open(64, 48, PixelFormat.YUYV)
    assert device.pixelformat == int.from_bytes(b"YUYV", "little")


def test_control_above_the_device_range_is_clamped_and_reported(device, source):
    source.open(32, 32, PixelFormat.RGB565)
    assert source.set_control("brightness", 200) == 127  # the device's maximum
    assert device.controls[0x00980900].value == 127


def test_control_is_rounded_to_the_device_step(device, source):
    source.open(32, 32, PixelFormat.RGB565)
    assert source.set_control("saturation", 65) == 64


def test_control_the_device_lacks_is_refused(device, source):
    del device.controls[CID_SATURATION]
    source.open(32, 32, PixelFormat.RGB565)
    with pytest.raises(UnsupportedControlError, match="no saturation control"):
        source.set_control("saturation", 10)


def test_disabled_control_is_refused(device, source):
    device.controls[CID_SATURATION].flags = 1
    source.open(32, 32, PixelFormat.RGB565)
    with pytest.raises(UnsupportedControlError, match="disabled"):
        source.set_control("saturation", 10)


def test_unknown_control_name_is_refused_listing_the_controls(device, source):
    source.open(32, 32, PixelFormat.RGB565)
    with pytest.raises(UnsupportedControlError, match=r"'zoom'.*brightness, contrast"):
        source.set_control("zoom", 1)


def test_eagain_after_a_wakeup_is_retried(device, source):
    source.open(32, 32, PixelFormat.RGB565)
    device.spurious_wakeups = 2
    assert bytes(source.read_frame()) == pattern_frame(0, 32, 32, 64)
    assert device.calls.count("DQBUF") >= 3


def test_busy_device_is_a_capture_error_with_ebusy(device, source):
    device.busy = True
    with pytest.raises(CameraCaptureError, match="busy") as caught:
        source.open(32, 32, PixelFormat.RGB565)
    assert caught.value.errno == errno.EBUSY
    assert isinstance(caught.value, OSError)


def test_busy_when_setting_the_format_is_reported_and_cleaned_up(device, source):
    device.busy_format = True
    with pytest.raises(CameraCaptureError, match="busy") as caught:
        source.open(32, 32, PixelFormat.RGB565)
    assert caught.value.errno == errno.EBUSY
    assert device.leaks() == []


def test_missing_device_names_its_path(device):
    src = V4L2Source("/dev/video7", syscalls=device)
    with pytest.raises(CameraCaptureError, match="/dev/video7: no such video device"):
        src.open(32, 32, PixelFormat.RGB565)


def test_no_frame_in_time_raises_a_timeout(device):
    device.stalled = True
    src = source_on(device, timeout_s=0.05)
    src.open(32, 32, PixelFormat.RGB565)
    with pytest.raises(CameraTimeoutError, match=r"no frame within 0\.05 s") as caught:
        src.read_frame()
    assert isinstance(caught.value, TimeoutError)
    src.close()


def test_newest_ready_frame_is_returned_and_older_ones_requeued(device, source):
    source.open(32, 32, PixelFormat.RGB565)
    device.produce(3)
    assert bytes(source.read_frame()) == pattern_frame(2, 32, 32, 64)
    assert sorted(device.queue) == sorted(
        i for i, b in enumerate(device.buffers) if b.state == "queued"
    )
    assert len(device.queue) == 3  # all but the one we hold
    assert bytes(source.read_frame()) == pattern_frame(3, 32, 32, 64)


def test_corrupted_frame_is_skipped_for_the_newest_good_one(device, source):
    source.open(32, 32, PixelFormat.RGB565)
    device.produce(1)
    device.corrupt_next = 1
    device.produce(1)  # frame 1 arrives flagged V4L2_BUF_FLAG_ERROR
    assert bytes(source.read_frame()) == pattern_frame(0, 32, 32, 64)


def test_output_only_device_is_refused(device, source):
    device.device_caps = 0x04000002  # streaming video output, no capture
    with pytest.raises(CameraCaptureError, match="not a streaming capture device"):
        source.open(32, 32, PixelFormat.RGB565)


def test_close_stops_unmaps_frees_and_is_idempotent(device):
    src = source_on(device)
    src.open(32, 32, PixelFormat.RGB565)
    frame = src.read_frame()
    del frame
    src.close()
    src.close()
    assert device.calls[-3:] == ["STREAMOFF", "REQBUFS", "close"]
    assert device.calls.count("close") == 1
    assert device.leaks() == []
    assert all(m.closed for m in device.maps)


def test_open_again_renegotiates_at_the_new_size(device, source):
    source.open(64, 48, PixelFormat.RGB565)
    source.read_frame()
    assert source.open(32, 32, PixelFormat.RGB565) == (32, 32, 64)
    assert device.calls.count("open") == 2 and len(device.fds) == 1
    assert len(bytes(source.read_frame())) == 64 * 32


def test_reading_before_open_is_an_error(source):
    with pytest.raises(CameraError, match="not open"):
        source.read_frame()


def test_camera_on_the_fake_device_delivers_the_exact_upright_image(device, thesis_table):
    device.stride_align = 64
    with Camera(source=source_on(device), width=80, height=60) as camera:
        camera.brightness = 200
        camera.enable(64)
        assert camera.update(0)
        assert camera.brightness == 127  # clamped by the device, reported as granted
        expected = thesis_table[pattern_codes(0, 80, 60)][::-1, ::-1]
        assert np.array_equal(camera.image, expected)
    assert device.leaks() == []
