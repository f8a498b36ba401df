"""RGB565 and YUYV to RGB888: exact against the thesis, every rotation, any stride."""

from __future__ import annotations

import tracemalloc

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ego.camera import (
    LUT5,
    LUT6,
    ROTATIONS,
    FrameSizeError,
    YuvFormula,
    rgb565_to_rgb888,
    rgb888_to_bgra,
    yuyv_to_rgb888,
)
from ego.camera.convert import opencv, opencv_is_exact
from ego.errors import OutOfRangeError

#: OpenCV is optional (the opencv extra; the Overo guide's "or nothing"): without it the
#: numpy backend, which every test here runs too, is the one that converts.
needs_opencv = pytest.mark.skipif(opencv() is None, reason="OpenCV is not installed (ego[opencv])")
BACKENDS = [pytest.param("opencv", marks=needs_opencv), "numpy"]
rng = np.random.default_rng(20240605)


def frame_bytes(codes: np.ndarray, byteorder: str, stride: int, pad: int = 0xEE) -> bytes:
    """Codes (h, w) laid out in rows of ``stride`` bytes, padding bytes set to ``pad``."""
    h, w = codes.shape
    rows = np.full((h, stride), pad, dtype=np.uint8)
    dtype = "<u2" if byteorder == "little" else ">u2"
    rows[:, : 2 * w] = codes.astype(dtype).view(np.uint8).reshape(h, 2 * w)
    return rows.tobytes()


def test_lut_constants_are_figure_4_7_of_the_thesis(thesis_luts):
    lut5, lut6 = thesis_luts
    assert np.array_equal(LUT5, lut5)
    assert np.array_equal(LUT6, lut6)
    assert LUT5[10] == 82  # the thesis' own worked example


@needs_opencv
def test_opencv_backend_passes_its_exactness_self_check():
    assert opencv_is_exact()


@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("byteorder", ["little", "big"])
@pytest.mark.parametrize("shape", [(256, 256), (4096, 16), (16, 4096)])
def test_every_rgb565_code_converts_to_the_thesis_table(thesis_table, backend, byteorder, shape):
    codes = np.arange(65536, dtype=np.uint16).reshape(shape)
    raw = frame_bytes(codes, byteorder, 2 * shape[1])
    rgb = rgb565_to_rgb888(raw, shape[1], shape[0], 0, byteorder, backend=backend)
    assert rgb.shape == (*shape, 3)
    mismatched = np.flatnonzero((rgb.reshape(-1, 3) != thesis_table).any(axis=1))
    assert mismatched.size == 0, f"codes {mismatched[:5]} differ from the thesis"


@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("byteorder", ["little", "big"])
@pytest.mark.parametrize("rotation", ROTATIONS)
@pytest.mark.parametrize(("width", "height", "stride"), [(37, 23, 74), (37, 23, 90), (8, 1, 17)])
def test_rotation_equals_np_rot90_of_the_unrotated_conversion(
    thesis_table, backend, byteorder, rotation, width, height, stride
):
    codes = rng.integers(0, 65536, (height, width)).astype(np.uint16)
    raw = frame_bytes(codes, byteorder, stride)
    rgb = rgb565_to_rgb888(
        raw, width, height, rotation, byteorder, stride_bytes=stride, backend=backend
    )
    expected = np.rot90(thesis_table[codes], rotation // 90)
    assert rgb.shape == expected.shape
    assert np.array_equal(rgb, expected)


def test_default_rotation_is_180_which_undoes_the_mounting(thesis_table):
    codes = rng.integers(0, 65536, (6, 10)).astype(np.uint16)
    rgb = rgb565_to_rgb888(frame_bytes(codes, "little", 20), 10, 6)
    assert np.array_equal(rgb, thesis_table[codes][::-1, ::-1])


@pytest.mark.parametrize("backend", BACKENDS)
def test_row_padding_bytes_never_reach_the_image(backend):
    codes = rng.integers(0, 65536, (9, 13)).astype(np.uint16)
    images = [
        rgb565_to_rgb888(
            frame_bytes(codes, "little", 40, pad), 13, 9, 90, stride_bytes=40, backend=backend
        )
        for pad in (0x00, 0xFF)
    ]
    assert np.array_equal(images[0], images[1])


@pytest.mark.parametrize("backend", BACKENDS)
def test_frame_at_an_odd_address_converts_exactly(thesis_table, backend):
    codes = rng.integers(0, 65536, (5, 7)).astype(np.uint16)
    raw = memoryview(b"\x00" + frame_bytes(codes, "little", 14))[1:]
    rgb = rgb565_to_rgb888(raw, 7, 5, 180, backend=backend)
    assert np.array_equal(rgb, thesis_table[codes][::-1, ::-1])


@pytest.mark.parametrize("backend", BACKENDS)
def test_out_is_filled_in_place_and_returned(backend):
    codes = rng.integers(0, 65536, (4, 6)).astype(np.uint16)
    out = np.zeros((6, 4, 3), dtype=np.uint8)
    result = rgb565_to_rgb888(frame_bytes(codes, "little", 12), 6, 4, 270, out=out, backend=backend)
    assert result is out
    assert out.any()


@pytest.mark.parametrize("backend", BACKENDS)
def test_repeated_conversion_allocates_no_frame_sized_buffer(backend):
    width, height = 320, 240
    raw = rng.integers(0, 256, 2 * width * height).astype(np.uint8).tobytes()
    out = np.empty((height, width, 3), dtype=np.uint8)
    rgb565_to_rgb888(raw, width, height, out=out, backend=backend)  # working buffers made
    tracemalloc.start()
    try:
        for _ in range(3):
            rgb565_to_rgb888(raw, width, height, out=out, backend=backend)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert peak < width * height  # far below one frame (2 bytes a pixel in, 3 out)


def test_out_of_the_wrong_shape_is_refused():
    with pytest.raises(ValueError, match="shape"):
        rgb565_to_rgb888(bytes(2 * 8 * 4), 8, 4, 90, out=np.empty((4, 8, 3), np.uint8))


def test_buffer_shorter_than_the_frame_raises_frame_size_error():
    with pytest.raises(FrameSizeError, match="needs 128 bytes"):
        rgb565_to_rgb888(bytes(127), 8, 8)


def test_stride_shorter_than_a_row_is_refused():
    with pytest.raises(FrameSizeError, match="stride 10"):
        rgb565_to_rgb888(bytes(200), 8, 8, stride_bytes=10)


@pytest.mark.parametrize("rotation", [45, -90, 360, 1])
def test_rotation_other_than_the_four_right_angles_is_refused(rotation):
    with pytest.raises(OutOfRangeError, match="0, 90, 180, 270"):
        rgb565_to_rgb888(bytes(32), 4, 4, rotation)


@pytest.mark.parametrize("size", [(0, 4), (4, -1)])
def test_non_positive_size_is_refused(size):
    with pytest.raises(OutOfRangeError, match="positive"):
        rgb565_to_rgb888(bytes(32), *size)


# -- YUYV -------------------------------------------------------------------------------------


def yuyv_frame(height: int, width: int, stride: int):
    """Random YUYV rows and the per-pixel (Y, U, V) they encode."""
    quads = rng.integers(0, 256, (height, width // 2, 4)).astype(np.uint8)
    rows = np.full((height, stride), 0x80, dtype=np.uint8)
    rows[:, : 2 * width] = quads.reshape(height, 2 * width)
    y = quads[..., [0, 2]].reshape(height, width).astype(np.int64)
    u = np.repeat(quads[..., 1], 2, axis=1).astype(np.int64)
    v = np.repeat(quads[..., 3], 2, axis=1).astype(np.int64)
    return rows.tobytes(), y, u, v


def float64_reference(formula: YuvFormula, y, u, v) -> np.ndarray:
    """The formula in float64 before any rounding: ITU-R float, or NTSC without its shift."""
    y, u, v = y.astype(float), u - 128.0, v - 128.0
    if formula is YuvFormula.ITU_R_FLOAT:
        rgb = [y + 1.402 * v, y - 0.344 * u - 0.714 * v, y + 1.772 * u]
    else:  # (298 (Y-16) + 409 V' + 128) >> 8 is this divided by 256, rounded
        c = y - 16
        rgb = [
            (298 * c + 409 * v) / 256,
            (298 * c - 100 * u - 208 * v) / 256,
            (298 * c + 516 * u) / 256,
        ]
    return np.clip(np.stack(rgb, axis=-1), 0, 255)


@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("rotation", ROTATIONS)
@pytest.mark.parametrize("formula", [YuvFormula.ITU_R_FLOAT, YuvFormula.NTSC])
def test_yuyv_formula_is_its_float64_reference_rounded(formula, rotation, backend):
    raw, y, u, v = yuyv_frame(11, 18, 44)
    rgb = yuyv_to_rgb888(raw, 18, 11, rotation, formula, stride_bytes=44, backend=backend)
    upright = np.rot90(rgb, -rotation // 90).astype(float)
    # Within 1 as asked, and in fact rounded: within a half (ties may go either way).
    assert np.abs(upright - float64_reference(formula, y, u, v)).max() <= 0.5 + 1e-3


def thesis_itu_r_integer(y: int, u: int, v: int) -> tuple[int, int, int]:
    """Section 4.2's ITU-R integer formula, one pixel, transliterated from the thesis."""
    u, v = u - 128, v - 128
    r = y + v + (v >> 2) + (v >> 3) + (v >> 5)
    g = y - ((u >> 2) + (u >> 4) + (u >> 5)) - ((v >> 1) + (v >> 3) + (v >> 5))
    b = y + u + (u >> 1) + (u >> 2) + (u >> 6)
    return tuple(min(255, max(0, c)) for c in (r, g, b))  # type: ignore[return-value]


@pytest.mark.parametrize("backend", BACKENDS)
def test_yuyv_itu_r_integer_is_exactly_the_thesis_shifts(backend):
    raw, y, u, v = yuyv_frame(16, 32, 64)
    rgb = yuyv_to_rgb888(raw, 32, 16, 0, "itu-r-integer", backend=backend)
    expected = [
        [thesis_itu_r_integer(int(y[r, c]), int(u[r, c]), int(v[r, c])) for c in range(32)]
        for r in range(16)
    ]
    assert rgb.tolist() == [[list(p) for p in row] for row in expected]


def test_yuyv_default_formula_is_itu_r_integer_and_rotation_180():
    raw, *_ = yuyv_frame(4, 6, 12)
    explicit = yuyv_to_rgb888(raw, 6, 4, 180, YuvFormula.ITU_R_INTEGER)
    assert np.array_equal(yuyv_to_rgb888(raw, 6, 4), explicit)


def test_yuyv_odd_width_is_refused():
    with pytest.raises(OutOfRangeError, match="even"):
        yuyv_to_rgb888(bytes(100), 5, 4)


def test_unknown_yuv_formula_is_refused():
    with pytest.raises(ValueError, match="bt709"):
        yuyv_to_rgb888(bytes(64), 4, 4, formula="bt709")


# -- BGRA for the Webots face ---------------------------------------------------------------


def test_bgra_is_blue_green_red_then_opaque_alpha():
    rgb = rng.integers(0, 256, (3, 5, 3)).astype(np.uint8)
    bgra = rgb888_to_bgra(rgb)
    assert np.array_equal(bgra[..., 0], rgb[..., 2])
    assert np.array_equal(bgra[..., 1], rgb[..., 1])
    assert np.array_equal(bgra[..., 2], rgb[..., 0])
    assert (bgra[..., 3] == 255).all()


# -- properties -------------------------------------------------------------------------------


@settings(max_examples=60, deadline=None)
@given(
    width=st.integers(1, 40),
    height=st.integers(1, 24),
    padding=st.integers(0, 9),
    rotation=st.sampled_from(ROTATIONS),
    byteorder=st.sampled_from(["little", "big"]),
    seed=st.integers(0, 2**32 - 1),
)
def test_any_geometry_converts_like_the_table_then_np_rot90(
    thesis_table, width, height, padding, rotation, byteorder, seed
):
    codes = np.random.default_rng(seed).integers(0, 65536, (height, width)).astype(np.uint16)
    stride = 2 * width + padding
    raw = frame_bytes(codes, byteorder, stride)
    rgb = rgb565_to_rgb888(raw, width, height, rotation, byteorder, stride_bytes=stride)
    assert np.array_equal(rgb, np.rot90(thesis_table[codes], rotation // 90))


# -- YUYV, ITU-R integer: every chroma pair, every rotation (the int16 shift path) ------------


def itu_r_integer_reference(y: np.ndarray, u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """The thesis' shifts on whole int64 arrays (numpy's >> is arithmetic, as on the Overo)."""
    u, v = u - 128, v - 128
    r = y + v + (v >> 2) + (v >> 3) + (v >> 5)
    g = y - ((u >> 2) + (u >> 4) + (u >> 5)) - ((v >> 1) + (v >> 3) + (v >> 5))
    b = y + u + (u >> 1) + (u >> 2) + (u >> 6)
    return np.clip(np.stack([r, g, b], axis=-1), 0, 255).astype(np.uint8)


def test_scalar_and_array_itu_r_integer_references_agree():
    y, u, v = (rng.integers(0, 256, 500) for _ in range(3))
    expected = [
        thesis_itu_r_integer(int(a), int(b), int(c)) for a, b, c in zip(y, u, v, strict=True)
    ]
    assert itu_r_integer_reference(y, u, v).tolist() == [list(p) for p in expected]


@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("luma", [(0, 255), (255, 0), (16, 235), (128, 127)])
def test_yuyv_itu_r_integer_is_exact_for_all_65536_chroma_pairs(backend, luma):
    """Each (U, V) once, with lumas at the clamps and in the middle: all saturations hit."""
    u, v = (a.reshape(256, 256) for a in np.meshgrid(np.arange(256), np.arange(256)))
    quads = np.stack([np.full_like(u, luma[0]), u, np.full_like(u, luma[1]), v], axis=-1)
    raw = quads.astype(np.uint8).tobytes()
    rgb = yuyv_to_rgb888(raw, 512, 256, 0, "itu-r-integer", backend=backend)
    y = np.tile(np.array(luma), (256, 256))
    assert np.array_equal(rgb, itu_r_integer_reference(y, np.repeat(u, 2, 1), np.repeat(v, 2, 1)))


@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("rotation", ROTATIONS)
@pytest.mark.parametrize(
    ("width", "height", "stride"), [(18, 11, 44), (52, 39, 104), (640, 48, 1282)]
)
def test_yuyv_itu_r_integer_every_rotation_is_np_rot90_of_the_reference(
    backend, rotation, width, height, stride
):
    raw, y, u, v = yuyv_frame(height, width, stride)
    # One byte in front: the frame starts at an odd address, as in a packet buffer.
    buffer = np.frombuffer(b"\0" + raw, np.uint8)[1:]
    rgb = yuyv_to_rgb888(buffer, width, height, rotation, stride_bytes=stride, backend=backend)
    expected = np.rot90(itu_r_integer_reference(y, u, v), rotation // 90)
    assert np.array_equal(rgb, expected)


@pytest.mark.parametrize(("width", "height"), [(True, 1), (1, True)])
def test_a_cached_geometry_still_refuses_a_bool_that_equals_it(width, height):
    rgb565_to_rgb888(bytes(2), 1, 1, 0)  # the plan for (1, 1, 0) is now cached
    with pytest.raises(OutOfRangeError):
        rgb565_to_rgb888(bytes(2), width, height, 0)
