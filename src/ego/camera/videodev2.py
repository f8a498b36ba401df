"""The kernel's V4L2 interface as ctypes sees it: structures, ioctl numbers, constants.

Written from the kernel's ``videodev2.h`` (the uapi header, which carries the syscall
exception to the kernel's GPL) and ``asm-generic/ioctl.h``; only what capture needs.

Structures are laid out with the platform's native alignment, as the C compiler does:
on the 32-bit Overo ``v4l2_buffer`` is 68 bytes, here (64-bit) 88; the request numbers
encode those sizes, so each build asks the kernel for the layout it actually passes.
"""

from __future__ import annotations

import ctypes
from typing import Final

from ego.camera.source import PixelFormat

__all__ = [
    "BUF_FLAG_ERROR",
    "BUF_TYPE_VIDEO_CAPTURE",
    "CAP_DEVICE_CAPS",
    "CAP_STREAMING",
    "CAP_VIDEO_CAPTURE",
    "CONTROL_IDS",
    "CTRL_FLAG_DISABLED",
    "FIELD_NONE",
    "FOURCC",
    "MEMORY_MMAP",
    "VIDIOC_DQBUF",
    "VIDIOC_G_CTRL",
    "VIDIOC_G_FMT",
    "VIDIOC_QBUF",
    "VIDIOC_QUERYBUF",
    "VIDIOC_QUERYCAP",
    "VIDIOC_QUERYCTRL",
    "VIDIOC_REQBUFS",
    "VIDIOC_STREAMOFF",
    "VIDIOC_STREAMON",
    "VIDIOC_S_CTRL",
    "VIDIOC_S_FMT",
    "IoctlArg",
    "fourcc",
    "v4l2_buffer",
    "v4l2_capability",
    "v4l2_control",
    "v4l2_format",
    "v4l2_pix_format",
    "v4l2_queryctrl",
    "v4l2_requestbuffers",
    "v4l2_timecode",
]


def fourcc(code: str) -> int:
    """A V4L2 four-character code as the kernel's ``v4l2_fourcc`` packs it."""
    a, b, c, d = (ord(ch) for ch in code)
    return a | (b << 8) | (c << 16) | (d << 24)


#: Our pixel formats as V4L2 codes: RGB565 'RGBP', RGB565X (big-endian) 'RGBR', 'YUYV'.
FOURCC: Final = {
    PixelFormat.RGB565: fourcc("RGBP"),
    PixelFormat.RGB565_BE: fourcc("RGBR"),
    PixelFormat.YUYV: fourcc("YUYV"),
}

_CID_BASE = 0x00980900
#: V4L2 control ids of the thesis' controls (V4L2_CID_BRIGHTNESS...).
CONTROL_IDS: Final = {
    "brightness": _CID_BASE + 0,
    "contrast": _CID_BASE + 1,
    "saturation": _CID_BASE + 2,
    "auto_white_balance": _CID_BASE + 12,
}

BUF_TYPE_VIDEO_CAPTURE = 1
MEMORY_MMAP = 1
FIELD_NONE = 1
CAP_VIDEO_CAPTURE = 0x00000001
CAP_STREAMING = 0x04000000
CAP_DEVICE_CAPS = 0x80000000
BUF_FLAG_ERROR = 0x00000040
CTRL_FLAG_DISABLED = 0x0001

_u8, _u32, _s32 = ctypes.c_uint8, ctypes.c_uint32, ctypes.c_int32


class v4l2_capability(ctypes.Structure):
    _fields_ = [
        ("driver", _u8 * 16),
        ("card", _u8 * 32),
        ("bus_info", _u8 * 32),
        ("version", _u32),
        ("capabilities", _u32),
        ("device_caps", _u32),
        ("reserved", _u32 * 3),
    ]


class v4l2_pix_format(ctypes.Structure):
    _fields_ = [
        (name, _u32)
        for name in (
            "width",
            "height",
            "pixelformat",
            "field",
            "bytesperline",
            "sizeimage",
            "colorspace",
            "priv",
            "flags",
            "ycbcr_enc",
            "quantization",
            "xfer_func",
        )
    ]


class _format_union(ctypes.Union):
    # v4l2_window holds pointers, which gives the union pointer alignment.
    _fields_ = [("pix", v4l2_pix_format), ("raw_data", _u8 * 200), ("_align", ctypes.c_void_p)]


class v4l2_format(ctypes.Structure):
    _fields_ = [("type", _u32), ("fmt", _format_union)]


class v4l2_requestbuffers(ctypes.Structure):
    _fields_ = [
        ("count", _u32),
        ("type", _u32),
        ("memory", _u32),
        ("capabilities", _u32),
        ("flags", _u8),
        ("reserved", _u8 * 3),
    ]


class _timeval(ctypes.Structure):
    _fields_ = [("tv_sec", ctypes.c_long), ("tv_usec", ctypes.c_long)]


class v4l2_timecode(ctypes.Structure):
    _fields_ = [
        ("type", _u32),
        ("flags", _u32),
        ("frames", _u8),
        ("seconds", _u8),
        ("minutes", _u8),
        ("hours", _u8),
        ("userbits", _u8 * 4),
    ]


class _buffer_m(ctypes.Union):
    _fields_ = [
        ("offset", _u32),
        ("userptr", ctypes.c_ulong),
        ("planes", ctypes.c_void_p),
        ("fd", _s32),
    ]


class v4l2_buffer(ctypes.Structure):
    _fields_ = [
        ("index", _u32),
        ("type", _u32),
        ("bytesused", _u32),
        ("flags", _u32),
        ("field", _u32),
        ("timestamp", _timeval),
        ("timecode", v4l2_timecode),
        ("sequence", _u32),
        ("memory", _u32),
        ("m", _buffer_m),
        ("length", _u32),
        ("reserved2", _u32),
        ("request_fd", _s32),
    ]


class v4l2_control(ctypes.Structure):
    _fields_ = [("id", _u32), ("value", _s32)]


class v4l2_queryctrl(ctypes.Structure):
    _fields_ = [
        ("id", _u32),
        ("type", _u32),
        ("name", _u8 * 32),
        ("minimum", _s32),
        ("maximum", _s32),
        ("step", _s32),
        ("default_value", _s32),
        ("flags", _u32),
        ("reserved", _u32 * 2),
    ]


_IOC_WRITE, _IOC_READ = 1, 2


def _ioc(direction: int, nr: int, struct: type[ctypes.Structure] | type[ctypes.c_int]) -> int:
    """asm-generic/ioctl.h: dir << 30 | size << 16 | 'V' << 8 | nr."""
    return (direction << 30) | (ctypes.sizeof(struct) << 16) | (ord("V") << 8) | nr


_RW = _IOC_READ | _IOC_WRITE
VIDIOC_QUERYCAP: Final = _ioc(_IOC_READ, 0, v4l2_capability)
VIDIOC_G_FMT: Final = _ioc(_RW, 4, v4l2_format)
VIDIOC_S_FMT: Final = _ioc(_RW, 5, v4l2_format)
VIDIOC_REQBUFS: Final = _ioc(_RW, 8, v4l2_requestbuffers)
VIDIOC_QUERYBUF: Final = _ioc(_RW, 9, v4l2_buffer)
VIDIOC_QBUF: Final = _ioc(_RW, 15, v4l2_buffer)
VIDIOC_DQBUF: Final = _ioc(_RW, 17, v4l2_buffer)
VIDIOC_STREAMON: Final = _ioc(_IOC_WRITE, 18, ctypes.c_int)
VIDIOC_STREAMOFF: Final = _ioc(_IOC_WRITE, 19, ctypes.c_int)
VIDIOC_G_CTRL: Final = _ioc(_RW, 27, v4l2_control)
VIDIOC_S_CTRL: Final = _ioc(_RW, 28, v4l2_control)
VIDIOC_QUERYCTRL: Final = _ioc(_RW, 36, v4l2_queryctrl)

IoctlArg = ctypes.Structure | ctypes.c_int
