"""RGB565 frames to RGB888, exactly the thesis' tables, the rotation fused in (section 5.1).

RGB565 -> RGB888 gives exactly the thesis' figure 4.7 look-up tables,
``LUT5[i] = round(i * 255 / 31)`` and ``LUT6[i] = round(i * 255 / 63)``, for every one of the
65,536 codes, in both byte orders: little-endian as V4L2 delivers ``RGBP`` on the Overo,
big-endian as the e-puck's Bluetooth camera sends it.

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
"""

from __future__ import annotations

import functools
import threading
from typing import Any, Final, Literal

import numpy as np

from ego.camera.convert.buffers import CACHE_SIZE
from ego.camera.convert.frame_checks import (
    Backend,
    ByteOrder,
    Image,
    byte_view,
    check_geometry,
    check_out,
    rotated_shape,
)
from ego.camera.convert.opencv import cv_rotate, opencv
from ego.seam.validate import check_rotation

#: Each thread's RGB565 plans (``.rgb565``: a dict, the eight most recent kept).
_PLANS = threading.local()

__all__ = ["LUT5", "LUT6", "RGB565_TABLE", "opencv_is_exact", "rgb565_to_rgb888"]


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


def _opencv_convert(codes: np.ndarray, dst: Image, tmp: Image) -> None:
    """Native little-endian codes (h, w) -> exact RGB888 in ``dst``; ``tmp`` same shape."""
    cv2 = opencv()
    assert cv2 is not None
    pairs = codes.view(np.uint8).reshape(codes.shape[0], codes.shape[1], 2)
    cv2.cvtColor(pairs, cv2.COLOR_BGR5652RGB, dst=tmp)
    cv2.transform(tmp, _WIDENED_TO_TABLE, dst=dst)


@functools.cache
def opencv_is_exact() -> bool:
    """Whether this OpenCV reproduces the thesis tables for all 65,536 codes (checked once).

    Two layouts are checked, 256 x 256 (vector code) and 65,536 x 1 (scalar tails).
    """
    if opencv() is None:
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
    flat = byte_view(raw, plan.needed, plan.what)
    codes = np.ndarray(plan.in_shape, plan.code_dtype, flat, 0, plan.strides)
    if (
        out is None
        or out.shape != plan.out_shape
        or out.dtype != np.uint8
        or not out.flags.c_contiguous
        or not out.flags.writeable
    ):
        out = check_out(out, plan.out_shape)
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
        oh, ow = rotated_shape(height, width, rotation)
        self.out_shape = (oh, ow, 3)
        self.k = rotation // 90
        self.cv_rotation = None if chosen == "numpy" else cv_rotate(rotation)
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
        cv2 = opencv()
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
    plans: dict[tuple[object, ...], _Rgb565Plan] | None = getattr(_PLANS, "rgb565", None)
    if plans is None:
        plans = _PLANS.rgb565 = {}
    # Keyed by plain ints only: True == 1 and 90.0 == 90 must still meet validation.
    plan = plans.get(key) if type(width) is type(height) is type(rotation) is int else None
    if plan is None:
        rotation = check_rotation(rotation)
        if byteorder not in ("little", "big"):
            raise ValueError(f"byteorder {byteorder!r} is not 'little' or 'big'")
        stride = check_geometry(width, height, 2, stride_bytes)
        plan = _Rgb565Plan(width, height, rotation, byteorder, stride, _pick_backend(backend))
        if len(plans) >= CACHE_SIZE:
            plans.pop(next(iter(plans)))
        plans[key] = plan
    return plan
