"""The thesis' three YUV422 -> RGB888 formulas (section 4.2), as per-byte tables and shifts."""

from __future__ import annotations

import functools
from enum import Enum

import numpy as np

from ego.camera.convert.buffers import Buffers

__all__ = ["YuvFormula", "itu_r_integer_chroma", "yuv_tables"]


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


@functools.cache
def yuv_tables(formula: YuvFormula) -> tuple[np.ndarray, np.ndarray, np.ndarray, int]:
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


def itu_r_integer_chroma(
    u: np.ndarray, v: np.ndarray, bufs: Buffers
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
