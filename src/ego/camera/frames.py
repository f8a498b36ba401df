"""A raw frame in any pixel format the camera grants, as RGB888: the one place that picks
the converter, shared by the Camera and by ``ego serve``'s encoded frames."""

from __future__ import annotations

from typing import Any, Literal

from ego.camera.convert import Image, YuvFormula, rgb565_to_rgb888, yuyv_to_rgb888
from ego.camera.source import GrantedFormat, PixelFormat

__all__ = ["frame_to_rgb888"]


def frame_to_rgb888(
    raw: Any,
    granted: GrantedFormat,
    pixel_format: PixelFormat,
    rotation: int,
    yuv_formula: YuvFormula = YuvFormula.ITU_R_INTEGER,
    out: Image | None = None,
) -> Image:
    """``raw`` (``granted.stride_bytes`` x ``granted.height`` bytes) converted and rotated
    (degrees counter-clockwise; 180 undoes the e-puck camera's mounting)."""
    if pixel_format is PixelFormat.YUYV:
        return yuyv_to_rgb888(
            raw,
            granted.width,
            granted.height,
            rotation,
            yuv_formula,
            stride_bytes=granted.stride_bytes,
            out=out,
        )
    order: Literal["little", "big"] = "big" if pixel_format is PixelFormat.RGB565_BE else "little"
    return rgb565_to_rgb888(
        raw,
        granted.width,
        granted.height,
        rotation,
        order,
        stride_bytes=granted.stride_bytes,
        out=out,
    )
