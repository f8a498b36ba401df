"""The Camera device: sampling schedule, image, size, rotation, controls, pixels, lifetime."""

from __future__ import annotations

import numpy as np
import pytest
from camera_fakes import ScriptedSource, pattern_codes

from ego.camera import Camera, PixelFormat, UnsupportedControlError
from ego.errors import CameraError, OutOfRangeError


@pytest.fixture
def source() -> ScriptedSource:
    return ScriptedSource()


@pytest.fixture
def camera(source: ScriptedSource):
    with Camera(source=source, width=48, height=36) as cam:
        yield cam


def test_enable_opens_the_source_at_the_sensor_size(camera, source):
    assert source.opened == []
    camera.enable(64)
    assert source.opened == [(48, 36, PixelFormat.RGB565)]
    assert camera.sampling_period == 64


def test_update_captures_only_when_due(camera, source):
    camera.enable(64)
    captured = [camera.update(t) for t in range(0, 257, 32)]
    assert captured == [True, False, True, False, True, False, True, False, True]
    assert source.reads == camera.frame_count == 5


def test_deadlines_are_absolute_and_do_not_drift(camera):
    camera.enable(50)
    times = [t for t in range(0, 1000, 30) if camera.update(t)]
    # Due at 0, 50, 100, ...: each capture happens at the first step on or after it.
    assert times == [
        0,
        60,
        120,
        150,
        210,
        270,
        300,
        360,
        420,
        450,
        510,
        570,
        600,
        660,
        720,
        750,
        810,
        870,
        900,
        960,
    ]


def test_after_a_stall_the_next_deadline_is_a_period_away(camera):
    camera.enable(50)
    camera.update(0)
    assert camera.update(500)  # a long stall: capture once...
    assert not camera.update(520)  # ...not a burst of the missed ones
    assert camera.update(550)


def test_disabled_camera_is_never_due(camera, source):
    camera.enable(10)
    camera.update(0)
    camera.disable()
    assert camera.sampling_period is None
    assert not camera.is_due(1000) and not camera.update(1000)
    assert source.reads == 1


@pytest.mark.parametrize("period", [0, -64])
def test_non_positive_period_is_refused(camera, period):
    with pytest.raises(OutOfRangeError, match="must be positive"):
        camera.enable(period)


def test_image_before_enable_or_first_frame_raises(camera):
    with pytest.raises(CameraError, match="not enabled"):
        camera.image  # noqa: B018
    camera.enable(64)
    with pytest.raises(CameraError, match="no frame yet"):
        camera.image  # noqa: B018


def test_image_is_the_upright_thesis_conversion(camera, thesis_table):
    camera.enable(64)
    camera.update(0)
    expected = thesis_table[pattern_codes(0, 48, 36)][::-1, ::-1]
    assert camera.image.shape == (36, 48, 3)
    assert np.array_equal(camera.image, expected)


def test_image_is_read_only_and_refreshed_in_place(camera):
    camera.enable(64)
    camera.update(0)
    first = camera.image
    before = first.copy()
    with pytest.raises(ValueError):
        first[0, 0, 0] = 1
    camera.update(64)
    assert not np.array_equal(first, before)  # the same buffer, now holding frame 2
    assert np.array_equal(first, camera.image)


def test_image_bgra_is_the_image_with_swapped_channels_and_alpha(camera):
    camera.enable(64)
    camera.update(0)
    bgra = np.frombuffer(camera.image_bgra(), np.uint8).reshape(36, 48, 4)
    assert np.array_equal(bgra[..., 2::-1], camera.image)
    assert (bgra[..., 3] == 255).all()
    camera.update(64)
    again = np.frombuffer(camera.image_bgra(), np.uint8).reshape(36, 48, 4)
    assert np.array_equal(again[..., 2::-1], camera.image)  # refreshed with the frame


@pytest.mark.parametrize(
    ("width", "height"), [(31, 32), (32, 31), (641, 480), (640, 481), (0, 0), (1000, 1000)]
)
def test_size_outside_32x32_to_640x480_is_refused_naming_the_range(camera, width, height):
    with pytest.raises(OutOfRangeError, match=r"32x32\.\.640x480"):
        camera.set_size(width, height)
    assert (camera.width, camera.height) == (48, 36)


def test_size_outside_the_range_is_refused_at_construction():
    with pytest.raises(OutOfRangeError, match=r"700x480 is outside 32x32\.\.640x480"):
        Camera(source=ScriptedSource(), width=700)


def test_set_size_reports_the_size_the_source_granted():
    source = ScriptedSource(grant=(48, 32))
    camera = Camera(source=source, width=40, height=32)
    camera.enable(64)
    assert (camera.width, camera.height) == (48, 32)
    assert camera.set_size(100, 80) == (48, 32)
    assert source.opened[-1][:2] == (100, 80)
    camera.update(0)
    assert camera.image.shape == (32, 48, 3)


def test_rotation_90_swaps_width_and_height_and_the_range(camera):
    camera.enable(64)
    camera.rotation = 90
    camera.update(0)
    assert (camera.width, camera.height) == (36, 48)
    assert camera.image.shape == (48, 36, 3)
    assert camera.set_size(480, 640) == (480, 640)
    assert camera.sensor_size == (640, 480)
    with pytest.raises(OutOfRangeError, match=r"32x32\.\.480x640 at rotation 90"):
        camera.set_size(640, 480)


@pytest.mark.parametrize("rotation", [45, 360, -90, True])
def test_rotation_other_than_0_90_180_270_is_refused(camera, rotation):
    with pytest.raises(OutOfRangeError, match="0, 90, 180, 270"):
        camera.rotation = rotation


def test_rotation_0_shows_the_sensor_frame_as_delivered(camera, thesis_table):
    camera.rotation = 0
    camera.enable(64)
    camera.update(0)
    assert np.array_equal(camera.image, thesis_table[pattern_codes(0, 48, 36)])


@pytest.mark.parametrize("fov", [0.0, -0.1, 3.2])
def test_field_of_view_outside_0_to_pi_is_refused(camera, fov):
    with pytest.raises(OutOfRangeError, match="outside"):
        camera.fov_rad = fov
    assert camera.fov_rad == pytest.approx(0.84)


def test_field_of_view_reaches_a_source_that_can_zoom():
    class ZoomingSource(ScriptedSource):
        def set_fov_rad(self, fov_rad: float) -> float:
            self.fov = fov_rad
            return fov_rad

    source = ZoomingSource()
    camera = Camera(source=source)
    camera.fov_rad = 0.5
    assert source.fov == 0.5 and camera.fov_rad == 0.5


def test_controls_set_before_enable_are_applied_when_the_source_opens(camera, source):
    camera.brightness = 1
    camera.contrast = 64
    assert source.controls == []
    camera.enable(64)
    assert source.controls == [("brightness", 1), ("contrast", 64)]


def test_control_value_reported_is_the_one_the_device_granted(camera):
    camera.enable(64)
    camera.saturation = 200  # within 0..255, but this source tops out at 100
    assert camera.saturation == 100


def test_controls_never_set_read_none_and_are_not_forced_on_the_device(camera, source):
    camera.enable(64)
    assert camera.brightness is None and camera.auto_white_balance is None
    assert source.controls == []


@pytest.mark.parametrize("name", ["brightness", "contrast", "saturation"])
@pytest.mark.parametrize("value", [-1, 256])
def test_control_outside_0_to_255_is_refused(camera, name, value):
    with pytest.raises(OutOfRangeError, match=f"{name} {value} is outside 0..255"):
        setattr(camera, name, value)


def test_control_that_is_not_an_integer_is_refused(camera):
    with pytest.raises(TypeError):
        camera.contrast = 12.5
    with pytest.raises(TypeError):
        camera.auto_white_balance = "yes"


def test_auto_white_balance_is_a_boolean(camera, source):
    camera.enable(64)
    camera.auto_white_balance = True
    assert camera.auto_white_balance is True
    assert source.controls == [("auto_white_balance", 1)]


def test_unknown_control_is_refused(camera):
    with pytest.raises(UnsupportedControlError, match="'hue'"):
        camera.set_control("hue", 3)


def test_pixel_accessors_read_the_image(camera):
    camera.enable(64)
    camera.update(0)
    r, g, b = (int(c) for c in camera.image[7, 11])
    assert (camera.get_red(11, 7), camera.get_green(11, 7), camera.get_blue(11, 7)) == (r, g, b)
    assert camera.get_grey(11, 7) == (r + g + b) // 3


@pytest.mark.parametrize(
    ("x", "y", "message"),
    [(48, 0, "x 48 is outside 0..47"), (-1, 0, "x -1"), (0, 36, "y 36 is outside 0..35")],
)
def test_pixel_outside_the_image_is_refused(camera, x, y, message):
    camera.enable(64)
    camera.update(0)
    with pytest.raises(OutOfRangeError, match=message):
        camera.get_red(x, y)


def test_save_image_writes_the_last_frame(camera, tmp_path):
    camera.enable(64)
    camera.update(0)
    camera.save_image(tmp_path / "frame.png")
    from PIL import Image

    assert np.array_equal(np.asarray(Image.open(tmp_path / "frame.png")), camera.image)


def test_big_endian_and_yuyv_sources_are_converted_by_their_format(thesis_table):
    codes = pattern_codes(0, 32, 32)
    big = Camera(
        source=ScriptedSource([codes.astype(">u2").tobytes()]),
        width=32,
        height=32,
        pixel_format=PixelFormat.RGB565_BE,
    )
    big.enable(64)
    big.update(0)
    assert np.array_equal(big.image, thesis_table[codes][::-1, ::-1])
    grey = bytes([128, 128] * 32 * 32)  # Y = 128, U = V = 128 everywhere: mid grey
    yuyv = Camera(source=ScriptedSource([grey]), width=32, height=32, pixel_format=PixelFormat.YUYV)
    yuyv.enable(64)
    yuyv.update(0)
    assert (yuyv.image == 128).all()


def test_close_is_idempotent_and_closes_the_source_once(source):
    camera = Camera(source=source)
    camera.enable(64)
    camera.close()
    camera.close()
    assert source.closes == 1
    assert not camera.is_due(0)
    with pytest.raises(CameraError, match="closed"):
        camera.enable(64)


def test_context_manager_closes_on_error(source):
    with pytest.raises(RuntimeError), Camera(source=source) as camera:
        camera.enable(64)
        raise RuntimeError("controller crashed")
    assert source.closes == 1


def test_repr_says_what_the_camera_is_doing(camera):
    camera.enable(64)
    assert repr(camera) == "<Camera 'camera' 48x36 rotation 180 RGB565, every 64 ms, 0 frames>"
