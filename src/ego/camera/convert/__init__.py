"""Raw camera frames to RGB888 (being split into modules by job)."""

from ego.camera.convert.rgb565 import (
    LUT5,
    LUT6,
    RGB565_TABLE,
    ROTATIONS,
    Backend,
    ByteOrder,
    Image,
    YuvFormula,
    check_rotation,
    cv2,
    opencv_is_exact,
    rgb565_to_rgb888,
    rgb888_to_bgra,
    yuyv_to_rgb888,
)

__all__ = [
    "LUT5",
    "LUT6",
    "RGB565_TABLE",
    "ROTATIONS",
    "Backend",
    "ByteOrder",
    "Image",
    "YuvFormula",
    "check_rotation",
    "cv2",
    "opencv_is_exact",
    "rgb565_to_rgb888",
    "rgb888_to_bgra",
    "yuyv_to_rgb888",
]
