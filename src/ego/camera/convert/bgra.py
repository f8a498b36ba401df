"""RGB888 to the BGRA bytes Webots' ``Camera.getImage`` returns (for the Webots face)."""

from __future__ import annotations

import numpy as np

from ego.camera.convert.frame_checks import Image, check_out
from ego.camera.convert.opencv import opencv

__all__ = ["rgb888_to_bgra"]


def rgb888_to_bgra(image: Image, out: Image | None = None) -> Image:
    """RGB888 ``(h, w, 3)`` -> BGRA ``(h, w, 4)`` with alpha 255, as Webots' getImage."""
    if image.ndim != 3 or image.shape[2] != 3 or image.dtype != np.uint8:
        raise ValueError(f"expected a (h, w, 3) uint8 image, not {image.dtype} {image.shape}")
    dst = check_out(out, (image.shape[0], image.shape[1], 4))
    cv2 = opencv()
    if cv2 is not None:
        cv2.cvtColor(np.ascontiguousarray(image), cv2.COLOR_RGB2BGRA, dst=dst)
    else:  # pragma: no cover
        dst[..., :3] = image[..., ::-1]
        dst[..., 3] = 255
    return dst
