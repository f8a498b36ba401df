"""YUYV (YUV422: Y0 U Y1 V) frames to RGB888 by a thesis formula, the rotation fused in.

Three paths give the same bytes: the ITU-R integer formula's shifts on whole int16 planes
(OpenCV splitting and merging, from 160x120 up), per-byte term tables looked up by
cv2.LUT, and the same tables gathered by numpy alone (no OpenCV).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ego.camera.convert.buffers import Buffers, buffers
from ego.camera.convert.frame_checks import (
    Backend,
    Image,
    byte_view,
    check_geometry,
    check_out,
    rotated_shape,
)
from ego.camera.convert.opencv import ZERO, cv_rotate, opencv
from ego.camera.convert.yuv_formulas import YuvFormula, itu_r_integer_chroma, yuv_tables
from ego.errors import OutOfRangeError
from ego.seam.validate import check_rotation

__all__ = ["yuyv_to_rgb888"]


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
    stride = check_geometry(width, height, 2, stride_bytes)
    if width % 2:
        raise OutOfRangeError(f"YUYV width {width} must be even (pixel pairs share U and V)")
    flat = byte_view(raw, stride * (height - 1) + 2 * width, f"a {width}x{height} YUYV frame")
    half = width // 2
    quads = np.ndarray((height, half, 4), np.uint8, flat, 0, (stride, 4, 1))
    oh, ow = rotated_shape(height, width, rotation)
    dst = check_out(out, (oh, ow, 3))

    bufs = buffers(("yuyv", width, height, stride, rotation, formula, backend))
    cv2 = None if backend == "numpy" else opencv()
    if (
        formula is YuvFormula.ITU_R_INTEGER
        and cv2 is not None
        and width * height >= _SHIFT_PATH_MIN_PIXELS
    ):
        if rotation in (0, 180):
            _yuyv_separable(quads, dst, bufs, rotation == 180)
            return dst
        upright = bufs.get("upright", (height, width, 3), np.uint8)
        _yuyv_separable(quads, upright, bufs, False)
        cv2.rotate(upright, cv_rotate(rotation), dst=dst)
        return dst
    luma_t, cu_t, cv_t, shift = yuv_tables(formula)
    upright = dst if rotation == 0 else bufs.get("upright", (height, width, 3), np.uint8)
    if cv2 is not None:
        _yuyv_opencv(quads, upright, bufs, luma_t, cu_t, cv_t, shift)
    else:
        _yuyv_numpy(quads, upright, bufs, luma_t, cu_t, cv_t, shift)
    if rotation:
        if cv2 is not None:
            cv2.rotate(upright, cv_rotate(rotation), dst=dst)
        else:  # pragma: no cover
            np.copyto(dst, np.rot90(upright, rotation // 90))
    return dst


#: Below this many pixels the int16 shift path's ~60 calls cost more than the per-byte
#: look-up path's ~25 (measured: 52x40 0.047 ms by look-ups, 0.064 ms by shifts; even at
#: 160x120; 2x faster by shifts at 640x480).
_SHIFT_PATH_MIN_PIXELS = 160 * 120


def _yuyv_separable(quads: np.ndarray, dst: Image, bufs: Buffers, turn: bool) -> None:
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
    cv2 = opencv()
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
    red, green, blue = itu_r_integer_chroma(planes[1], planes[3], bufs)
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
    bufs: Buffers,
    luma_t: np.ndarray,
    cu_t: np.ndarray,
    cv_t: np.ndarray,
    shift: int,
) -> None:
    """Planes out (Y0, U, Y1, V), per-byte terms by cv2.LUT, sums in numpy, pixels back in."""
    cv2 = opencv()
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
                cv2.add(acc, ZERO, dst=outs[3 * j + c], dtype=cv2.CV_8U)
            else:
                # Saturating to CV_8U clamps to 0..255 (and rounds half to even, like
                # np.rint, for the float formula) in the same pass as the sum.
                cv2.add(lumas[j], chroma, dst=outs[3 * j + c], dtype=cv2.CV_8U)
    cv2.merge(outs, dst=upright.reshape(height, half, 6))


def _yuyv_numpy(
    quads: np.ndarray,
    upright: Image,
    bufs: Buffers,
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
