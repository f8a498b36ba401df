"""OpenCV for the conversions and the encodings, imported at first need, and the constants
they hand it.

Importing OpenCV costs a board about 70 MB of resident memory (Debian's build, on the
emulated armhf Overo: benchmarks/results/board_insns.md) and a second or more of start.
A controller that never converts a frame must not pay that, so importing ``ego.camera``
imports no OpenCV: :func:`opencv` imports it the first time a conversion or an encoding
asks, and answers None where it is not installed (then NumPy and Pillow do the work).
"""

from __future__ import annotations

import functools
import importlib
from types import ModuleType
from typing import Final

import numpy as np

__all__ = ["ZERO", "cv_rotate", "opencv"]

# cv2.add's scalar 0. OpenCV takes an array as a scalar only if it is float64 of 1 or 4
# elements: 4.6 (Debian bookworm's) asserts on any other type; later versions convert.
ZERO: Final = np.zeros(1, dtype=np.float64)


@functools.cache
def opencv() -> ModuleType | None:
    """The ``cv2`` module, imported on the first call; None where OpenCV is not installed."""
    try:
        return importlib.import_module("cv2")
    except ImportError:
        return None


def cv_rotate(rotation: int) -> int | None:
    """OpenCV's rotation code for ``rotation`` degrees counter-clockwise (90, 180, 270);
    None for 0, or without OpenCV."""
    cv2 = opencv()
    if cv2 is None or rotation == 0:
        return None
    codes: dict[int, int] = {
        90: cv2.ROTATE_90_COUNTERCLOCKWISE,
        180: cv2.ROTATE_180,
        270: cv2.ROTATE_90_CLOCKWISE,
    }
    return codes[rotation]
