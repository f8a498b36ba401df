"""Raw camera frames to RGB888, with the rotation fused in (thesis sections 4.2 and 5.1).

RGB565 -> RGB888 gives exactly the thesis' figure 4.7 look-up tables,
``LUT5[i] = round(i * 255 / 31)`` and ``LUT6[i] = round(i * 255 / 63)``, for every one of the
65,536 codes, in both byte orders: little-endian as V4L2 delivers ``RGBP`` on the Overo,
big-endian as the e-puck's Bluetooth camera sends it. YUYV (YUV422) -> RGB888 uses any of
the thesis' three formulas. ``rotation`` (degrees counter-clockwise, as ``np.rot90``) is
applied in the same call; its default, 180, undoes the upside-down camera mounting.

How RGB565 is made fast and still exact (measured at 640x480, rotation 180, one thread,
each alone, on the machine where the thesis' own C loop, ``thesis_fused.c`` with gcc
-O2, takes 0.31 ms; ``benchmarks/camera_convert.py`` times them side by side):

========================================================  ========
numpy gather, 65,536-entry (R, G, B) table, ``np.take``     0.75 ms
numpy gather, uint32 table, then drop the fourth byte        0.33 ms
**OpenCV: rotate the 16-bit codes, cvtColor, transform**   **0.19 ms**
========================================================  ========

A numpy gather cannot beat the C loop: ``np.take`` first widens the 16-bit codes to
8-byte indices, then reads one table entry per pixel from a 256 kB table, about as much
work as the C loop's three reads from 96 bytes. The winner instead rotates the 2-byte
codes with OpenCV (cheaper than rotating 3-byte pixels), widens each field with
``cvtColor(COLOR_BGR5652RGB)`` (R and B become ``8 * i``, G ``4 * i``: shifts, not the
thesis' values), and scales and rounds every channel in one SIMD pass with
``cv2.transform`` and the diagonal matrix ``(255/248, 255/252, 255/248)``. That is
exact: ``round(8i * 255/248) = round(i * 255/31)``, and no ``i`` lands nearer than 1/126
to a half (1/62 for R and B), far beyond float32 error. Because it leans on OpenCV's
arithmetic, it is checked against the tables, all 65,536 codes through both OpenCV's
vector and scalar paths, the first time it is used; if the check fails (an OpenCV build
that rounds differently) or OpenCV is missing, the numpy gather (one ``np.take`` of
whole 3-byte pixels through a rotated view of the codes) is used instead; ``backend=``
forces either one.

Working buffers are allocated once per (geometry, rotation, byte order, backend) and kept
(per thread, the eight most recent); no Python loop touches a pixel.
"""

from __future__ import annotations

import functools
import threading
from collections import OrderedDict
from enum import Enum
from typing import Any, Final, Literal

import numpy as np
import numpy.typing as npt

from ego.errors import FrameSizeError, OutOfRangeError
from ego.seam.validate import ROTATIONS, check_rotation

try:
    import cv2
except ImportError:  # pragma: no cover - opencv-python-headless is a dependency
    cv2 = None  # type: ignore[assignment]

__all__ = [
    "LUT5",
    "LUT6",
    "RGB565_TABLE",
    "ROTATIONS",
    "Backend",
    "ByteOrder",
    "YuvFormula",
    "check_rotation",
    "opencv_is_exact",
    "rgb565_to_rgb888",
    "rgb888_to_bgra",
    "yuyv_to_rgb888",
]

Image = npt.NDArray[np.uint8]
ByteOrder = Literal["little", "big"]
Backend = Literal["auto", "opencv", "numpy"]


_i5 = np.arange(32, dtype=np.int64)
_i6 = np.arange(64, dtype=np.int64)
#: Thesis figure 4.7, 5 bits -> 8 bits: round(i * 255 / 31) (no i falls on a half).
LUT5: Final[Image] = ((_i5 * 255 + 15) // 31).astype(np.uint8)
#: Thesis figure 4.7, 6 bits -> 8 bits: round(i * 255 / 63).
LUT6: Final[Image] = ((_i6 * 255 + 31) // 63).astype(np.uint8)
LUT5.flags.writeable = False
LUT6.flags.writeable = False

_codes = np.arange(65536, dtype=np.int64)
#: Every RGB565 code (R in the top 5 bits) -> its RGB888 pixel, shape (65536, 3).
RGB565_TABLE: Final[Image] = np.stack(
    [LUT5[_codes >> 11], LUT6[(_codes >> 5) & 63], LUT5[_codes & 31]], axis=1
)
RGB565_TABLE.flags.writeable = False
# The same table as one 3-byte item per code, for a single np.take per frame.
_TABLE_V3: Final = np.ascontiguousarray(RGB565_TABLE).view("V3").reshape(65536)

# cvtColor leaves R and B as 8*i and G as 4*i; this matrix turns them into the tables.
_WIDENED_TO_TABLE: Final = np.diag([255.0 / 248.0, 255.0 / 252.0, 255.0 / 248.0])

# cv2.add's scalar 0. OpenCV takes an array as a scalar only if it is float64 of 1 or 4
# elements: 4.6 (Debian bookworm's) asserts on any other type; later versions convert.
_ZERO: Final = np.zeros(1, dtype=np.float64)

_CV_ROTATE: Final[dict[int, int]] = (
    {}
    if cv2 is None
    else {
        90: cv2.ROTATE_90_COUNTERCLOCKWISE,
        180: cv2.ROTATE_180,
        270: cv2.ROTATE_90_CLOCKWISE,
    }
)


class YuvFormula(str, Enum):
    """The thesis' three YUV422 -> RGB888 formulas (section 4.2)."""

    #: R = Y + 1.402 V', G = Y - 0.344 U' - 0.714 V', B = Y + 1.772 U' (U' = U - 128...),
    #: computed in float32 and rounded to the nearest integer.
    ITU_R_FLOAT = "itu-r-float"
    #: (298 (Y-16) + 409 V' + 128) >> 8 and so on: the integer NTSC (BT.601 video range).
    NTSC = "ntsc"
    #: Shifts and adds only, the thesis' fastest and its default. Printed in the thesis
    #: as G = Y - ((U'>>2) + (U'>>4) + (U'>>5)) - ((V'>>1) + (V'>>3) + (V'>>5)) ("14
    #: additions and 12 shifts"), so its G weighs V' by 0.656 where ITU-R says 0.714:
    #: it is an approximation by design, reproduced here as printed.
    ITU_R_INTEGER = "itu-r-integer"


# -- validation -------------------------------------------------------------------------


def _check_geometry(width: int, height: int, bytes_per_pixel: int, stride: int | None) -> int:
    for name, value in (("width", width), ("height", height)):
        if not isinstance(value, (int, np.integer)) or isinstance(value, bool) or value < 1:
            raise OutOfRangeError(f"frame {name} {value!r} must be a positive integer")
    row = width * bytes_per_pixel
    if stride is None:
        return row
    if stride < row:
        raise FrameSizeError(f"row stride {stride} bytes is shorter than a {width}-pixel row")
    return int(stride)


def _byte_view(raw: Any, needed: int, what: str) -> np.ndarray:
    """The raw buffer as flat bytes (no copy), checked to be long enough."""
    flat = np.frombuffer(raw, dtype=np.uint8) if not isinstance(raw, np.ndarray) else raw
    if flat.dtype != np.uint8 or flat.ndim != 1:
        flat = np.ascontiguousarray(flat).reshape(-1).view(np.uint8)
    if flat.size < needed:
        raise FrameSizeError(f"{what} needs {needed} bytes but the buffer holds {flat.size}")
    return flat


def _check_out(out: Image | None, shape: tuple[int, int, int]) -> Image:
    if out is None:
        return np.empty(shape, dtype=np.uint8)
    if out.shape != shape or out.dtype != np.uint8:
        raise ValueError(f"out must be a uint8 array of shape {shape}, not {out.dtype} {out.shape}")
    if not out.flags.c_contiguous or not out.flags.writeable:
        raise ValueError("out must be C-contiguous and writeable")
    return out


def _rotated_shape(height: int, width: int, rotation: int) -> tuple[int, int]:
    return (width, height) if rotation in (90, 270) else (height, width)


# -- buffers kept between calls -----------------------------------------------------------


class _Buffers:
    """Working arrays for one geometry, made on first use."""

    def __init__(self) -> None:
        self.arrays: dict[str, np.ndarray] = {}

    def get(self, name: str, shape: tuple[int, ...], dtype: npt.DTypeLike) -> np.ndarray:
        array = self.arrays.get(name)
        if array is None or array.shape != shape or array.dtype != np.dtype(dtype):
            array = self.arrays[name] = np.empty(shape, dtype=dtype)
        return array


_CACHE_SIZE = 8
_local = threading.local()


def _buffers(key: tuple[Any, ...]) -> _Buffers:
    """The working buffers for ``key`` in this thread (the eight most recent are kept)."""
    cache: OrderedDict[tuple[Any, ...], _Buffers] | None = getattr(_local, "cache", None)
    if cache is None:
        cache = _local.cache = OrderedDict()
    found = cache.get(key)
    if found is None:
        found = cache[key] = _Buffers()
        if len(cache) > _CACHE_SIZE:
            cache.popitem(last=False)
    else:
        cache.move_to_end(key)
    return found


# -- RGB565 -------------------------------------------------------------------------------


def _opencv_convert(codes: np.ndarray, dst: Image, tmp: Image) -> None:
    """Native little-endian codes (h, w) -> exact RGB888 in ``dst``; ``tmp`` same shape."""
    assert cv2 is not None
    pairs = codes.view(np.uint8).reshape(codes.shape[0], codes.shape[1], 2)
    cv2.cvtColor(pairs, cv2.COLOR_BGR5652RGB, dst=tmp)
    cv2.transform(tmp, _WIDENED_TO_TABLE, dst=dst)


@functools.cache
def opencv_is_exact() -> bool:
    """Whether this OpenCV reproduces the thesis tables for all 65,536 codes (checked once).

    Two layouts are checked, 256 x 256 (vector code) and 65,536 x 1 (scalar tails).
    """
    if cv2 is None:
        return False
    all_codes = np.arange(65536, dtype="<u2")
    for shape in ((256, 256), (65536, 1)):
        codes = all_codes.reshape(shape)
        dst = np.empty((*shape, 3), dtype=np.uint8)
        _opencv_convert(codes, dst, np.empty_like(dst))
        if not np.array_equal(dst.reshape(-1, 3), RGB565_TABLE):
            return False
    return True


def _pick_backend(backend: Backend) -> Literal["opencv", "numpy"]:
    if backend == "numpy":
        return "numpy"
    if backend == "opencv":
        if not opencv_is_exact():
            raise ValueError("the OpenCV backend is unavailable or inexact on this build")
        return "opencv"
    if backend != "auto":
        raise ValueError(f"backend {backend!r} is not one of 'auto', 'opencv', 'numpy'")
    return "opencv" if opencv_is_exact() else "numpy"


def rgb565_to_rgb888(
    raw: Any,
    width: int,
    height: int,
    rotation: int = 180,
    byteorder: ByteOrder = "little",
    *,
    stride_bytes: int | None = None,
    out: Image | None = None,
    backend: Backend = "auto",
) -> Image:
    """Convert one RGB565 frame to RGB888 and rotate it, exactly as the thesis' tables.

    Args:
        raw: the frame, any buffer (bytes, memoryview of an mmap, numpy array); rows of
            ``width`` 2-byte pixels, R in the top five bits.
        width, height: the frame as the sensor delivered it, in pixels.
        rotation: degrees counter-clockwise, 0, 90, 180 (default: undoes the mounting) or 270.
        byteorder: ``"little"`` (V4L2 ``RGBP``) or ``"big"`` (the e-puck's Bluetooth camera).
        stride_bytes: bytes from one row to the next (V4L2 ``bytesperline``); default
            ``2 * width``.
        out: a C-contiguous uint8 array to write into, shape ``(h', w', 3)``.
        backend: ``"auto"`` (OpenCV when it passed its exactness check, else numpy),
            ``"opencv"`` or ``"numpy"``.

    Returns:
        ``(h', w', 3)`` uint8 RGB, ``(height, width)`` for 0/180 and ``(width, height)``
        for 90/270; ``out`` if given.
    """
    plan = _rgb565_plan(width, height, rotation, byteorder, stride_bytes, backend)
    flat = _byte_view(raw, plan.needed, plan.what)
    codes = np.ndarray(plan.in_shape, plan.code_dtype, flat, 0, plan.strides)
    if (
        out is None
        or out.shape != plan.out_shape
        or out.dtype != np.uint8
        or not out.flags.c_contiguous
        or not out.flags.writeable
    ):
        out = _check_out(out, plan.out_shape)
    plan.run(codes, out)
    return out


class _Rgb565Plan:
    """One validated (geometry, rotation, byte order, backend) with its working buffers.

    Made once per thread and key, so a call on a small frame (Webots' 52x39) costs little
    more than its three OpenCV passes.
    """

    def __init__(
        self, width: int, height: int, rotation: int, byteorder: ByteOrder, stride: int, chosen: str
    ) -> None:
        self.in_shape = (height, width)
        self.strides = (stride, 2)
        self.needed = stride * (height - 1) + 2 * width
        self.what = f"a {width}x{height} RGB565 frame"
        self.code_dtype = np.dtype("<u2" if byteorder == "little" else ">u2")
        oh, ow = _rotated_shape(height, width, rotation)
        self.out_shape = (oh, ow, 3)
        self.k = rotation // 90
        self.cv_rotation = _CV_ROTATE.get(rotation)
        self.numpy = chosen == "numpy"
        self.swap = byteorder == "big"
        if self.numpy:
            # take() converts its indices to intp: into this buffer, not a new frame each call.
            self.index = np.empty((oh, ow), np.intp)
        else:
            self.widened = np.empty(self.out_shape, np.uint8)
            self.native = np.empty((oh, ow), "<u2")
            self.native_pairs = self.native.view(np.uint8).reshape(oh, ow, 2)

    def run(self, codes: np.ndarray, dst: Image) -> None:
        if self.numpy:
            # One gather: the rotation is a view of the codes, the table holds whole pixels.
            view = dst.view("V3").reshape(dst.shape[:2])
            np.copyto(self.index, np.rot90(codes, self.k))
            np.take(_TABLE_V3, self.index, out=view, mode="clip")
            return
        assert cv2 is not None
        if self.swap or not codes.flags.aligned:
            # One numpy pass swaps (or aligns) the codes and rotates them at the same time.
            np.copyto(self.native, np.rot90(codes, self.k))
        elif self.cv_rotation is not None:
            cv2.rotate(codes, self.cv_rotation, dst=self.native)
        else:
            _opencv_convert(codes, dst, self.widened)
            return
        cv2.cvtColor(self.native_pairs, cv2.COLOR_BGR5652RGB, dst=self.widened)
        cv2.transform(self.widened, _WIDENED_TO_TABLE, dst=dst)


def _rgb565_plan(
    width: int,
    height: int,
    rotation: int,
    byteorder: ByteOrder,
    stride_bytes: int | None,
    backend: Backend,
) -> _Rgb565Plan:
    """The plan for these arguments in this thread (validated on first use)."""
    key = (width, height, rotation, byteorder, stride_bytes, backend)
    plans: dict[tuple[object, ...], _Rgb565Plan] | None = getattr(_local, "rgb565", None)
    if plans is None:
        plans = _local.rgb565 = {}
    # Keyed by plain ints only: True == 1 and 90.0 == 90 must still meet validation.
    plan = plans.get(key) if type(width) is type(height) is type(rotation) is int else None
    if plan is None:
        rotation = check_rotation(rotation)
        if byteorder not in ("little", "big"):
            raise ValueError(f"byteorder {byteorder!r} is not 'little' or 'big'")
        stride = _check_geometry(width, height, 2, stride_bytes)
        plan = _Rgb565Plan(width, height, rotation, byteorder, stride, _pick_backend(backend))
        if len(plans) >= _CACHE_SIZE:
            plans.pop(next(iter(plans)))
        plans[key] = plan
    return plan


# -- YUYV ---------------------------------------------------------------------------------


@functools.cache
def _yuv_tables(formula: YuvFormula) -> tuple[np.ndarray, np.ndarray, np.ndarray, int]:
    """Per-byte terms: ``luma[Y]`` (256,), ``chroma_u[c][U]`` and ``chroma_v[c][V]`` (3, 256).

    Each channel c is ``clamp((luma[Y] + chroma_u[c][U] + chroma_v[c][V]) >> shift)``
    (rounded instead of shifted for the float formula), exactly the thesis' formulas.
    """
    b = np.arange(256, dtype=np.int32)
    d = b - 128  # U' and V'
    zero = np.zeros(256, dtype=np.int32)
    if formula is YuvFormula.ITU_R_FLOAT:
        f = d.astype(np.float32)
        luma_f = b.astype(np.float32)
        cu = np.stack([np.zeros(256, np.float32), np.float32(-0.344) * f, np.float32(1.772) * f])
        cv = np.stack([np.float32(1.402) * f, np.float32(-0.714) * f, np.zeros(256, np.float32)])
        return luma_f, cu, cv, 0
    if formula is YuvFormula.NTSC:
        luma = 298 * (b - 16) + 128
        cu = np.stack([zero, -100 * d, 516 * d])
        cv = np.stack([409 * d, -208 * d, zero])
        return luma, cu, cv, 8
    if formula is YuvFormula.ITU_R_INTEGER:
        # numpy's >> on signed integers is arithmetic, as the C code's on the Overo.
        cu = np.stack([zero, -((d >> 2) + (d >> 4) + (d >> 5)), d + (d >> 1) + (d >> 2) + (d >> 6)])
        cv = np.stack([d + (d >> 2) + (d >> 3) + (d >> 5), -((d >> 1) + (d >> 3) + (d >> 5)), zero])
        return b, cu, cv, 0
    raise ValueError(f"unknown YUV formula {formula!r}")  # pragma: no cover


def yuyv_to_rgb888(
    raw: Any,
    width: int,
    height: int,
    rotation: int = 180,
    formula: YuvFormula | str = YuvFormula.ITU_R_INTEGER,
    *,
    stride_bytes: int | None = None,
    out: Image | None = None,
    backend: Backend = "auto",
) -> Image:
    """Convert one YUYV (YUV422: Y0 U Y1 V) frame to RGB888 with a thesis formula, and rotate.

    Arguments as :func:`rgb565_to_rgb888`; ``width`` must be even (two pixels share U, V).
    ``formula``: :class:`YuvFormula` or its value; default the thesis' ITU-R integer one.
    Exact to the formula whichever ``backend`` (``"auto"``/``"opencv"`` use OpenCV to
    split and merge the planes and to look the per-byte terms up; ``"numpy"`` does not).
    """
    rotation = check_rotation(rotation)
    formula = YuvFormula(formula)
    stride = _check_geometry(width, height, 2, stride_bytes)
    if width % 2:
        raise OutOfRangeError(f"YUYV width {width} must be even (pixel pairs share U and V)")
    flat = _byte_view(raw, stride * (height - 1) + 2 * width, f"a {width}x{height} YUYV frame")
    half = width // 2
    quads = np.ndarray((height, half, 4), np.uint8, flat, 0, (stride, 4, 1))
    oh, ow = _rotated_shape(height, width, rotation)
    dst = _check_out(out, (oh, ow, 3))

    bufs = _buffers(("yuyv", width, height, stride, rotation, formula, backend))
    if (
        formula is YuvFormula.ITU_R_INTEGER
        and backend != "numpy"
        and cv2 is not None
        and width * height >= _SHIFT_PATH_MIN_PIXELS
    ):
        if rotation in (0, 180):
            _yuyv_separable(quads, dst, bufs, rotation == 180)
            return dst
        upright = bufs.get("upright", (height, width, 3), np.uint8)
        _yuyv_separable(quads, upright, bufs, False)
        cv2.rotate(upright, _CV_ROTATE[rotation], dst=dst)
        return dst
    luma_t, cu_t, cv_t, shift = _yuv_tables(formula)
    upright = dst if rotation == 0 else bufs.get("upright", (height, width, 3), np.uint8)
    if backend != "numpy" and cv2 is not None:
        _yuyv_opencv(quads, upright, bufs, luma_t, cu_t, cv_t, shift)
    else:
        _yuyv_numpy(quads, upright, bufs, luma_t, cu_t, cv_t, shift)
    if rotation:
        if cv2 is not None:
            cv2.rotate(upright, _CV_ROTATE[rotation], dst=dst)
        else:  # pragma: no cover
            np.copyto(dst, np.rot90(upright, rotation // 90))
    return dst


#: Below this many pixels the int16 shift path's ~60 calls cost more than the per-byte
#: look-up path's ~25 (measured: 52x40 0.047 ms by look-ups, 0.064 ms by shifts; even at
#: 160x120; 2x faster by shifts at 640x480).
_SHIFT_PATH_MIN_PIXELS = 160 * 120


def _yuyv_separable(quads: np.ndarray, dst: Image, bufs: _Buffers, turn: bool) -> None:
    """ITU-R integer YUYV -> RGB888 (upright, or turned 180 degrees), shifts in int16 numpy.

    That formula is ``clamp(Y + c(U, V))`` with each chroma term a sum of arithmetic
    shifts of ``U - 128`` or ``V - 128``: the terms are computed once per pixel pair in
    int16 (a shifted plane shifted further gives the next term, as ``(d >> 2) >> 1 ==
    d >> 3``), added to each pair's two lumas, clamped, narrowed to uint8, and
    interleaved by two OpenCV merges (pairs into rows, then channels into pixels). Every
    step is a whole-plane SIMD pass; cv2.LUT on a byte plane costs some twenty times a
    saturating add here, so none is used. Turning by 180 degrees is done on the 4-byte
    pairs first (two thirds of the output's bytes), each pair's two pixels then swapping.
    """
    assert cv2 is not None
    height, half = quads.shape[:2]
    if turn:
        quads = cv2.rotate(quads, cv2.ROTATE_180, dst=bufs.get("turned", quads.shape, np.uint8))
    planes = [bufs.get(f"in{i}", (height, half), np.uint8) for i in range(4)]
    cv2.split(quads, planes)
    lumas = []
    for j, plane in enumerate((planes[2], planes[0]) if turn else (planes[0], planes[2])):
        lumas.append(bufs.get(f"luma{j}", (height, half), np.int16))
        np.copyto(lumas[j], plane)  # widened once: mixed-type sums are buffered and slow
    red, green, blue = _itu_r_integer_chroma(planes[1], planes[3], bufs)
    acc = bufs.get("acc", (height, half), np.int16)
    rows = []
    for c, chroma in enumerate((red, green, blue)):
        pair = [bufs.get(f"out{c}{j}", (height, half), np.uint8) for j in (0, 1)]
        for j, luma in enumerate(lumas):
            np.add(luma, chroma, out=acc)
            # Clamp to 0..255: x if x > -1 else 0, then min(x, 255) (int16 SIMD passes;
            # numpy's maximum with a scalar is ten times slower here).
            cv2.threshold(acc, -1, 0, cv2.THRESH_TOZERO, dst=acc)
            cv2.threshold(acc, 255, 0, cv2.THRESH_TRUNC, dst=acc)
            np.copyto(pair[j], acc, casting="unsafe")
        rows.append(cv2.merge(pair, dst=bufs.get(f"row{c}", (height, half, 2), np.uint8)))
    cv2.merge([row.reshape(height, 2 * half) for row in rows], dst=dst)


def _itu_r_integer_chroma(
    u: np.ndarray, v: np.ndarray, bufs: _Buffers
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per pair, the thesis' shift-and-add chroma terms of R, G and B (int16 planes)."""
    shape = u.shape
    du = np.subtract(u, 128, out=bufs.get("du", shape, np.int16), dtype=np.int16)
    dv = np.subtract(v, 128, out=bufs.get("dv", shape, np.int16), dtype=np.int16)
    t = bufs.get("shifted", shape, np.int16)
    red = bufs.get("red", shape, np.int16)
    np.copyto(red, dv)
    neg_green = bufs.get("neg_green", shape, np.int16)
    # R = Y + V' + (V'>>2) + (V'>>3) + (V'>>5); G's V part (V'>>1) + (V'>>3) + (V'>>5).
    np.right_shift(dv, 1, out=t)
    np.copyto(neg_green, t)
    t >>= 1
    red += t
    t >>= 1
    red += t
    neg_green += t
    t >>= 2
    red += t
    neg_green += t
    # B = Y + U' + (U'>>1) + (U'>>2) + (U'>>6); G's U part (U'>>2) + (U'>>4) + (U'>>5).
    blue = bufs.get("blue", shape, np.int16)
    np.copyto(blue, du)
    np.right_shift(du, 1, out=t)
    blue += t
    t >>= 1
    blue += t
    neg_green += t
    t >>= 2
    neg_green += t
    t >>= 1
    neg_green += t
    t >>= 1
    blue += t
    green = np.negative(neg_green, out=neg_green)
    return red, green, blue


def _finish(acc: np.ndarray, shift: int, dst: np.ndarray) -> None:
    """``acc`` (the formula's sum) -> shifted or rounded, clamped to 0..255, into ``dst``."""
    if shift:
        acc >>= shift
    elif acc.dtype.kind == "f":
        np.rint(acc, out=acc)
    np.clip(acc, 0, 255, out=acc)
    np.copyto(dst, acc, casting="unsafe")


def _yuyv_opencv(
    quads: np.ndarray,
    upright: Image,
    bufs: _Buffers,
    luma_t: np.ndarray,
    cu_t: np.ndarray,
    cv_t: np.ndarray,
    shift: int,
) -> None:
    """Planes out (Y0, U, Y1, V), per-byte terms by cv2.LUT, sums in numpy, pixels back in."""
    assert cv2 is not None
    height, half = quads.shape[:2]
    kind = luma_t.dtype
    planes = [bufs.get(f"in{i}", (height, half), np.uint8) for i in range(4)]
    cv2.mixChannels([quads], planes, [0, 0, 1, 1, 2, 2, 3, 3])
    y0, u, y1, v = planes
    lumas = (
        cv2.LUT(y0, luma_t, dst=bufs.get("luma0", (height, half), kind)),
        cv2.LUT(y1, luma_t, dst=bufs.get("luma1", (height, half), kind)),
    )
    chroma = bufs.get("chroma", (height, half), kind)
    term = bufs.get("term", (height, half), kind)
    acc = bufs.get("acc", (height, half), kind)
    # Output planes in pixel order: R0 G0 B0 R1 G1 B1, one (h, w/2, 6) merge = (h, w, 3).
    outs = [bufs.get(f"out{i}", (height, half), np.uint8) for i in range(6)]
    for c in range(3):
        # R has no U term and B no V term in any of the formulas: skip the zero tables.
        terms = [(p, t) for p, t in ((u, cu_t[c]), (v, cv_t[c])) if t.any()]
        cv2.LUT(terms[0][0], terms[0][1], dst=chroma)
        for p, t in terms[1:]:
            chroma += cv2.LUT(p, t, dst=term)
        for j in (0, 1):
            if shift:
                np.add(lumas[j], chroma, out=acc)
                acc >>= shift
                cv2.add(acc, _ZERO, dst=outs[3 * j + c], dtype=cv2.CV_8U)
            else:
                # Saturating to CV_8U clamps to 0..255 (and rounds half to even, like
                # np.rint, for the float formula) in the same pass as the sum.
                cv2.add(lumas[j], chroma, dst=outs[3 * j + c], dtype=cv2.CV_8U)
    cv2.merge(outs, dst=upright.reshape(height, half, 6))


def _yuyv_numpy(
    quads: np.ndarray,
    upright: Image,
    bufs: _Buffers,
    luma_t: np.ndarray,
    cu_t: np.ndarray,
    cv_t: np.ndarray,
    shift: int,
) -> None:
    """The same sums with numpy alone (no OpenCV): gathers and strided stores."""
    height, half = quads.shape[:2]
    kind = luma_t.dtype
    chroma = bufs.get("chroma", (height, half), kind)
    acc = bufs.get("acc", (height, half), kind)
    lumas = (np.take(luma_t, quads[..., 0]), np.take(luma_t, quads[..., 2]))
    pairs = upright.reshape(height, half, 2, 3)
    for c in range(3):
        np.take(cu_t[c], quads[..., 1], out=chroma)
        chroma += np.take(cv_t[c], quads[..., 3])
        for j in (0, 1):
            np.add(lumas[j], chroma, out=acc)
            _finish(acc, shift, pairs[:, :, j, c])


# -- for the Webots face -------------------------------------------------------------------


def rgb888_to_bgra(image: Image, out: Image | None = None) -> Image:
    """RGB888 ``(h, w, 3)`` -> BGRA ``(h, w, 4)`` with alpha 255, as Webots' getImage."""
    if image.ndim != 3 or image.shape[2] != 3 or image.dtype != np.uint8:
        raise ValueError(f"expected a (h, w, 3) uint8 image, not {image.dtype} {image.shape}")
    dst = _check_out(out, (image.shape[0], image.shape[1], 4))
    if cv2 is not None:
        cv2.cvtColor(np.ascontiguousarray(image), cv2.COLOR_RGB2BGRA, dst=dst)
    else:  # pragma: no cover
        dst[..., :3] = image[..., ::-1]
        dst[..., 3] = 255
    return dst
