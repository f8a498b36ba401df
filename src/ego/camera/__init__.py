"""The e-puck camera: V4L2 capture, exact RGB565/YUYV conversion with fused rotation, encoding.

>>> from ego.camera import Camera, V4L2Source, rgb565_to_rgb888
>>> camera = Camera(source=V4L2Source("/dev/video0"), width=320, height=240)  # doctest: +SKIP
"""

from ego.camera.config import CameraConfiguration, parse_configuration, read_configuration
from ego.camera.convert import (
    LUT5,
    LUT6,
    RGB565_TABLE,
    ROTATIONS,
    YuvFormula,
    rgb565_to_rgb888,
    rgb888_to_bgra,
    yuyv_to_rgb888,
)
from ego.camera.device import DEFAULT_FOV_RAD, Camera
from ego.camera.encode import encode_jpeg, encode_png, save_image
from ego.camera.source import (
    CONTROLS,
    FileReplaySource,
    FrameSource,
    GrantedFormat,
    PixelFormat,
)
from ego.camera.v4l2 import V4L2Source
from ego.camera.v4l2_syscalls import LinuxSyscalls, V4L2Syscalls
from ego.errors import (
    CameraTimeoutError,
    ConfigSyntaxError,
    FrameSizeError,
    ImageFormatError,
    SettingOutOfRangeError,
    UnknownSettingError,
    UnsupportedControlError,
)

__all__ = [
    "CONTROLS",
    "DEFAULT_FOV_RAD",
    "LUT5",
    "LUT6",
    "RGB565_TABLE",
    "ROTATIONS",
    "Camera",
    "CameraConfiguration",
    "CameraTimeoutError",
    "ConfigSyntaxError",
    "FileReplaySource",
    "FrameSizeError",
    "FrameSource",
    "GrantedFormat",
    "ImageFormatError",
    "LinuxSyscalls",
    "PixelFormat",
    "SettingOutOfRangeError",
    "UnknownSettingError",
    "UnsupportedControlError",
    "V4L2Source",
    "V4L2Syscalls",
    "YuvFormula",
    "encode_jpeg",
    "encode_png",
    "parse_configuration",
    "read_configuration",
    "rgb565_to_rgb888",
    "rgb888_to_bgra",
    "save_image",
    "yuyv_to_rgb888",
]
