"""Capture from a V4L2 video device (the Overo's camera): ctypes structs, ioctls, mmap streaming.

Why a small layer of our own rather than a library:

- linuxpy, the complete Python V4L2 binding, is GPL-3.0; ego is MIT and runs inside
  users' controllers, which a GPL dependency would bind to the GPL's terms.
- OpenCV's V4L2 backend (``cv2.VideoCapture``) negotiates only the pixel formats it
  knows how to convert itself, and cannot open a camera that offers RGB565 alone, as
  the e-puck's does on the Overo; it also hides the row stride and the controls.
- What the camera needs is small: query the capabilities, set the format, map a few
  buffers, queue/dequeue them, four controls: some 400 lines of code here (a third of
  them struct declarations, one field a line), written from the kernel's
  ``videodev2.h`` (the uapi header, which carries the syscall exception to the
  kernel's GPL).

All system calls go through a :class:`V4L2Syscalls` object (``open``, ``ioctl``,
``mmap``, ``select``, ``close``), :class:`LinuxSyscalls` by default; tests pass an
in-process fake device instead, which decodes the same request numbers and struct
bytes, so the code path below is the one that runs on the robot.

Structures are laid out with the platform's native alignment, as the C compiler does:
on the 32-bit Overo ``v4l2_buffer`` is 68 bytes, here (64-bit) 88; the request numbers
encode those sizes, so each build asks the kernel for the layout it actually passes.
"""

from __future__ import annotations

import contextlib
import ctypes
import errno
import fcntl
import logging
import mmap
import os
import select
import time
from typing import Final, Protocol

from ego.camera.source import GrantedFormat, PixelFormat, check_control_name
from ego.errors import CameraCaptureError, CameraError, CameraTimeoutError, UnsupportedControlError

__all__ = [
    "CONTROL_IDS",
    "DEFAULT_CAMERA_DEVICE",
    "FOURCC",
    "LinuxSyscalls",
    "V4L2Source",
    "V4L2Syscalls",
    "fourcc",
]

#: The Overo's camera, unless EGO_CAMERA names another device (or "none").
DEFAULT_CAMERA_DEVICE = "/dev/video0"

log = logging.getLogger(__name__)

# -- videodev2.h ---------------------------------------------------------------------------


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

# -- the system-call seam ------------------------------------------------------------------


class V4L2Syscalls(Protocol):
    """The five system calls capture needs; each raises ``OSError`` with the errno."""

    def open(self, path: str, flags: int) -> int: ...

    def ioctl(self, fd: int, request: int, arg: IoctlArg) -> None:
        """Run ``request``; the kernel reads and writes ``arg`` in place."""
        ...

    def mmap(self, fd: int, length: int, offset: int) -> mmap.mmap: ...

    def select(self, fd: int, timeout_s: float) -> bool:
        """Whether ``fd`` became readable (a frame is ready) within ``timeout_s``."""
        ...

    def close(self, fd: int) -> None: ...


class LinuxSyscalls:
    """The real thing: os.open, fcntl.ioctl, mmap.mmap, select.select, os.close."""

    def open(self, path: str, flags: int) -> int:
        return os.open(path, flags)

    def ioctl(self, fd: int, request: int, arg: IoctlArg) -> None:
        fcntl.ioctl(fd, request, arg, True)

    def mmap(self, fd: int, length: int, offset: int) -> mmap.mmap:
        prot = mmap.PROT_READ | mmap.PROT_WRITE
        return mmap.mmap(fd, length, mmap.MAP_SHARED, prot, offset=offset)

    def select(self, fd: int, timeout_s: float) -> bool:
        readable, _, _ = select.select([fd], [], [], timeout_s)
        return bool(readable)

    def close(self, fd: int) -> None:
        os.close(fd)


# -- the source ----------------------------------------------------------------------------


def _text(field: ctypes.Array[ctypes.c_uint8]) -> str:
    return bytes(field).split(b"\0", 1)[0].decode("ascii", "replace")


#: Why a video device would not open, for the errors ENOENT, EBUSY, EACCES.
_OPEN_REASONS = {
    errno.ENOENT: "no such video device",
    errno.EBUSY: "the device is busy: another program is using it",
    errno.EACCES: "permission denied (is the user in the 'video' group?)",
}


def _clamped(query: v4l2_queryctrl, value: int) -> int:
    """``value`` within the control's range, on its step, as the driver would take it."""
    clamped = min(max(int(value), query.minimum), query.maximum)
    if query.step > 1:
        clamped -= (clamped - query.minimum) % query.step
    return int(clamped)


class V4L2Source:
    """Frames from a V4L2 capture device, streamed through memory-mapped buffers.

    ``read_frame`` returns a view of the newest filled buffer (older ready frames are
    handed back to the driver: the camera wants the present, not a queue); the view stays
    valid until the next ``read_frame`` or ``close``.

    >>> with Camera(source=V4L2Source("/dev/video0")) as camera:  # doctest: +SKIP
    ...     camera.enable(64)
    """

    def __init__(
        self,
        device: str = DEFAULT_CAMERA_DEVICE,
        *,
        syscalls: V4L2Syscalls | None = None,
        buffer_count: int = 4,
        timeout_s: float = 2.0,
    ) -> None:
        if buffer_count < 1:
            raise ValueError(f"buffer_count {buffer_count} must be at least 1")
        self.device = device
        self.buffer_count = buffer_count
        self.timeout_s = timeout_s
        self.driver = ""
        self.card = ""
        self._sys: V4L2Syscalls = syscalls if syscalls is not None else LinuxSyscalls()
        self._fd: int | None = None
        self._maps: list[mmap.mmap] = []
        self._streaming = False
        self._requested = False  # buffers were requested (REQBUFS 0 frees them)
        self._held: int | None = None  # the buffer whose view read_frame last returned
        self._view: memoryview | None = None

    # -- helpers ---------------------------------------------------------------------

    def _ioctl(self, request: int, arg: IoctlArg, what: str) -> None:
        assert self._fd is not None
        while True:
            try:
                self._sys.ioctl(self._fd, request, arg)
                return
            except InterruptedError:
                continue
            except OSError as exc:
                code = exc.errno or errno.EIO
                if code == errno.EBUSY:
                    message = f"{self.device} is busy ({what}): another program is using it"
                else:
                    message = f"{self.device}: {what} failed: {os.strerror(code)}"
                raise CameraCaptureError(code, message) from exc

    def _buffer(self, index: int = 0) -> v4l2_buffer:
        return v4l2_buffer(index=index, type=BUF_TYPE_VIDEO_CAPTURE, memory=MEMORY_MMAP)

    def _queue(self, index: int) -> None:
        self._ioctl(VIDIOC_QBUF, self._buffer(index), f"queueing buffer {index}")

    def _dequeue(self) -> v4l2_buffer | None:
        """The next filled buffer, or None if none is ready (EAGAIN)."""
        buf = self._buffer()
        try:
            self._ioctl(VIDIOC_DQBUF, buf, "dequeueing a frame")
        except CameraCaptureError as exc:
            if exc.errno == errno.EAGAIN:
                return None
            raise
        if buf.flags & BUF_FLAG_ERROR:  # a corrupted frame: give it back, look again
            log.debug("%s: buffer %d flagged as corrupted, skipped", self.device, buf.index)
            self._queue(buf.index)
            return self._dequeue()
        return buf

    # -- FrameSource -------------------------------------------------------------------

    def open(self, width: int, height: int, pixel_format: PixelFormat) -> GrantedFormat:
        """Open (or re-open at a new size), negotiate the format, map buffers, stream."""
        self.close()
        code = FOURCC[PixelFormat(pixel_format)]
        try:
            self._fd = self._sys.open(self.device, os.O_RDWR | os.O_NONBLOCK)
        except OSError as exc:
            code_ = exc.errno or errno.EIO
            reason = _OPEN_REASONS.get(code_) or os.strerror(code_)
            raise CameraCaptureError(code_, f"cannot open {self.device}: {reason}") from exc
        try:
            return self._start(self._fd, width, height, PixelFormat(pixel_format), code)
        except BaseException:
            self.close()
            raise

    def _start(
        self, fd: int, width: int, height: int, pixel_format: PixelFormat, code: int
    ) -> GrantedFormat:
        cap = v4l2_capability()
        self._ioctl(VIDIOC_QUERYCAP, cap, "querying capabilities")
        self.driver, self.card = _text(cap.driver), _text(cap.card)
        caps = cap.device_caps if cap.capabilities & CAP_DEVICE_CAPS else cap.capabilities
        if not caps & CAP_VIDEO_CAPTURE or not caps & CAP_STREAMING:
            raise CameraCaptureError(
                errno.ENODEV,
                f"{self.device} ({self.driver} {self.card!r}) is not a streaming capture device",
            )

        fmt = v4l2_format(type=BUF_TYPE_VIDEO_CAPTURE)
        pix = fmt.fmt.pix
        pix.width, pix.height, pix.pixelformat, pix.field = width, height, code, FIELD_NONE
        self._ioctl(VIDIOC_S_FMT, fmt, f"setting {width}x{height} {pixel_format.value}")
        if pix.pixelformat != code:  # drivers substitute a format they have
            offered = bytes(pix.pixelformat.to_bytes(4, "little")).decode("ascii", "replace")
            raise CameraCaptureError(
                errno.EINVAL,
                f"{self.device} cannot deliver {pixel_format.value}; it offers {offered!r}",
            )
        granted_w, granted_h = int(pix.width), int(pix.height)
        stride = int(pix.bytesperline) or 2 * granted_w  # 0 means "packed" for some drivers
        if stride < 2 * granted_w:
            raise CameraCaptureError(errno.EINVAL, f"{self.device} gave a {stride}-byte stride")
        if (granted_w, granted_h) != (width, height):
            log.info(
                "%s: asked %dx%d, granted %dx%d", self.device, width, height, granted_w, granted_h
            )

        req = v4l2_requestbuffers(
            count=self.buffer_count, type=BUF_TYPE_VIDEO_CAPTURE, memory=MEMORY_MMAP
        )
        self._ioctl(VIDIOC_REQBUFS, req, "requesting buffers")
        self._requested = True
        if req.count < 1:
            raise CameraCaptureError(errno.ENOMEM, f"{self.device} granted no capture buffers")
        for index in range(req.count):
            buf = self._buffer(index)
            self._ioctl(VIDIOC_QUERYBUF, buf, f"querying buffer {index}")
            try:
                self._maps.append(self._sys.mmap(fd, buf.length, buf.m.offset))
            except OSError as exc:
                raise CameraCaptureError(
                    exc.errno or errno.EIO, f"{self.device}: mapping buffer {index} failed"
                ) from exc
        for index in range(req.count):
            self._queue(index)
        self._ioctl(VIDIOC_STREAMON, ctypes.c_int(BUF_TYPE_VIDEO_CAPTURE), "starting the stream")
        self._streaming = True
        return GrantedFormat(granted_w, granted_h, stride)

    def read_frame(self) -> memoryview:
        """The newest frame; waits up to ``timeout_s`` for one (CameraTimeoutError)."""
        fd = self._fd
        if fd is None or not self._streaming:
            raise CameraError(f"{self.device} is not open: call open() first")
        self._release_view()
        if self._held is not None:
            held, self._held = self._held, None
            self._queue(held)
        deadline = time.monotonic() + self.timeout_s
        newest: v4l2_buffer | None = None
        while newest is None:
            remaining = deadline - time.monotonic()
            if remaining <= 0 or not self._sys.select(fd, remaining):
                raise CameraTimeoutError(
                    errno.ETIMEDOUT, f"{self.device}: no frame within {self.timeout_s} s"
                )
            newest = self._dequeue()  # None: woken, but not ready after all (EAGAIN)
        while (newer := self._dequeue()) is not None:  # drain: keep only the newest
            self._queue(newest.index)
            newest = newer
        self._held = newest.index
        mapped = self._maps[newest.index]
        used = newest.bytesused or newest.length
        self._view = memoryview(mapped)[:used]
        return self._view

    def set_control(self, name: str, value: int) -> int:
        """Set a control, clamped to the device's range and step; return what it took."""
        check_control_name(name)
        if self._fd is None:
            raise CameraError(f"{self.device} is not open: call open() first")
        query = v4l2_queryctrl(id=CONTROL_IDS[name])
        try:
            self._ioctl(VIDIOC_QUERYCTRL, query, f"querying control {name}")
        except CameraCaptureError as exc:
            if exc.errno != errno.EINVAL:
                raise
            raise UnsupportedControlError(f"{self.device} has no {name} control") from exc
        if query.flags & CTRL_FLAG_DISABLED:
            raise UnsupportedControlError(f"{self.device}'s {name} control is disabled")
        clamped = _clamped(query, value)
        if clamped != value:
            log.info(
                "%s: %s %d clamped to %d (device range %d..%d)",
                self.device,
                name,
                value,
                clamped,
                query.minimum,
                query.maximum,
            )
        self._ioctl(VIDIOC_S_CTRL, v4l2_control(id=query.id, value=clamped), f"setting {name}")
        readback = v4l2_control(id=query.id)
        self._ioctl(VIDIOC_G_CTRL, readback, f"reading {name}")
        return int(readback.value)

    def _release_view(self) -> None:
        if self._view is not None:
            with contextlib.suppress(BufferError):  # still in use: the GC frees it later
                self._view.release()
            self._view = None

    def close(self) -> None:
        """Stop streaming, unmap, free the buffers, close the device; safe to call twice."""
        if self._fd is None:
            return
        fd, self._fd = self._fd, None
        if self._streaming:
            self._quiet_ioctl(fd, VIDIOC_STREAMOFF, ctypes.c_int(BUF_TYPE_VIDEO_CAPTURE))
        self._streaming = False
        self._held = None
        self._release_view()
        for mapped in self._maps:
            try:
                mapped.close()
            except BufferError:  # a caller still holds the frame: unmapped when it lets go
                log.warning(
                    "%s: a frame is still in use; its buffer is unmapped later", self.device
                )
        if self._maps or self._requested:
            free = v4l2_requestbuffers(count=0, type=BUF_TYPE_VIDEO_CAPTURE, memory=MEMORY_MMAP)
            self._quiet_ioctl(fd, VIDIOC_REQBUFS, free)
        self._maps = []
        self._requested = False
        try:
            self._sys.close(fd)
        except OSError as exc:  # pragma: no cover - nothing more to do if close(2) fails
            log.debug("%s: close: %s", self.device, exc)

    def _quiet_ioctl(self, fd: int, request: int, arg: IoctlArg) -> None:
        """An ioctl while closing: failures are logged, the kernel cleans up on close."""
        try:
            self._sys.ioctl(fd, request, arg)
        except OSError as exc:
            log.debug("%s: ioctl %#x while closing: %s", self.device, request, exc)

    def __repr__(self) -> str:
        state = "streaming" if self._streaming else "closed" if self._fd is None else "open"
        return f"V4L2Source({self.device!r}, {state})"
