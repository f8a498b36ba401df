"""OpenCV for the conversions when it is installed, and the constants they hand it."""

from __future__ import annotations

from typing import Final

import numpy as np

try:
    import cv2
except ImportError:  # pragma: no cover - opencv-python-headless is a dependency
    cv2 = None  # type: ignore[assignment]

__all__ = ["CV_ROTATE", "ZERO", "cv2"]

# cv2.add's scalar 0. OpenCV takes an array as a scalar only if it is float64 of 1 or 4
# elements: 4.6 (Debian bookworm's) asserts on any other type; later versions convert.
ZERO: Final = np.zeros(1, dtype=np.float64)

CV_ROTATE: Final[dict[int, int]] = (
    {}
    if cv2 is None
    else {
        90: cv2.ROTATE_90_COUNTERCLOCKWISE,
        180: cv2.ROTATE_180,
        270: cv2.ROTATE_90_CLOCKWISE,
    }
)
