"""Raw camera frames to RGB888, with the rotation fused in (thesis sections 4.2 and 5.1).

RGB565 -> RGB888 gives exactly the thesis' figure 4.7 look-up tables in both byte
orders (:mod:`~ego.camera.convert.rgb565`, which also says how it is made fast); YUYV
(YUV422) -> RGB888 uses any of the thesis' three formulas
(:mod:`~ego.camera.convert.yuv_formulas`, run by :mod:`~ego.camera.convert.yuyv`).
``rotation`` (degrees counter-clockwise, as ``np.rot90``) is applied in the same call;
its default, 180, undoes the upside-down camera mounting.

Working buffers are allocated once per (geometry, rotation, byte order, backend) and kept
(per thread, the eight most recent: :mod:`~ego.camera.convert.buffers`); no Python loop
touches a pixel.

One job a module: ``frame_checks`` (geometry, buffer and ``out`` checks), ``buffers``,
``opencv`` (OpenCV, imported at first need, and its constants), ``rgb565``, ``yuv_formulas``,
``yuyv`` and ``bgra`` (RGB888 to Webots' BGRA).
"""

from ego.camera.convert.bgra import rgb888_to_bgra
from ego.camera.convert.frame_checks import Backend, ByteOrder, Image
from ego.camera.convert.opencv import opencv
from ego.camera.convert.rgb565 import LUT5, LUT6, RGB565_TABLE, opencv_is_exact, rgb565_to_rgb888
from ego.camera.convert.yuv_formulas import YuvFormula
from ego.camera.convert.yuyv import yuyv_to_rgb888
from ego.seam.validate import ROTATIONS, check_rotation

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
    "opencv",
    "opencv_is_exact",
    "rgb565_to_rgb888",
    "rgb888_to_bgra",
    "yuyv_to_rgb888",
]
