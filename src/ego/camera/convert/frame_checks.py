"""The checks every conversion makes: frame geometry, the raw buffer, ``out``, the turned shape."""

from __future__ import annotations

from typing import Any, Literal

import numpy as np
import numpy.typing as npt

from ego.errors import FrameSizeError, OutOfRangeError

__all__ = [
    "Backend",
    "ByteOrder",
    "Image",
    "byte_view",
    "check_geometry",
    "check_out",
    "rotated_shape",
]

Image = npt.NDArray[np.uint8]
ByteOrder = Literal["little", "big"]
Backend = Literal["auto", "opencv", "numpy"]


def check_geometry(width: int, height: int, bytes_per_pixel: int, stride: int | None) -> int:
    for name, value in (("width", width), ("height", height)):
        if not isinstance(value, (int, np.integer)) or isinstance(value, bool) or value < 1:
            raise OutOfRangeError(f"frame {name} {value!r} must be a positive integer")
    row = width * bytes_per_pixel
    if stride is None:
        return row
    if stride < row:
        raise FrameSizeError(f"row stride {stride} bytes is shorter than a {width}-pixel row")
    return int(stride)


def byte_view(raw: Any, needed: int, what: str) -> np.ndarray:
    """The raw buffer as flat bytes (no copy), checked to be long enough."""
    flat = np.frombuffer(raw, dtype=np.uint8) if not isinstance(raw, np.ndarray) else raw
    if flat.dtype != np.uint8 or flat.ndim != 1:
        flat = np.ascontiguousarray(flat).reshape(-1).view(np.uint8)
    if flat.size < needed:
        raise FrameSizeError(f"{what} needs {needed} bytes but the buffer holds {flat.size}")
    return flat


def check_out(out: Image | None, shape: tuple[int, int, int]) -> Image:
    if out is None:
        return np.empty(shape, dtype=np.uint8)
    if out.shape != shape or out.dtype != np.uint8:
        raise ValueError(f"out must be a uint8 array of shape {shape}, not {out.dtype} {out.shape}")
    if not out.flags.c_contiguous or not out.flags.writeable:
        raise ValueError("out must be C-contiguous and writeable")
    return out


def rotated_shape(height: int, width: int, rotation: int) -> tuple[int, int]:
    return (width, height) if rotation in (90, 270) else (height, width)
