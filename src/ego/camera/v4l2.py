"""Capture from a V4L2 video device (the Overo's camera): format, controls, mmap streaming.

Why a small layer of our own rather than a library:

- linuxpy, the complete Python V4L2 binding, is GPL-3.0; ego is MIT and runs inside
  users' controllers, which a GPL dependency would bind to the GPL's terms.
- OpenCV's V4L2 backend (``cv2.VideoCapture``) negotiates only the pixel formats it
  knows how to convert itself, and cannot open a camera that offers RGB565 alone, as
  the e-puck's does on the Overo; it also hides the row stride and the controls.
- What the camera needs is small: query the capabilities, set the format, map a few
  buffers, queue/dequeue them, four controls: some 400 lines of code (this module, the
  structures and request numbers in :mod:`ego.camera.videodev2`, written from the
  kernel's ``videodev2.h``, the uapi header, which carries the syscall exception to the
  kernel's GPL).

All system calls go through a :class:`~ego.camera.v4l2_syscalls.V4L2Syscalls` object
(``open``, ``ioctl``, ``mmap``, ``select``, ``close``),
:class:`~ego.camera.v4l2_syscalls.LinuxSyscalls` by default; tests pass an in-process
fake device instead, which decodes the same request numbers and struct bytes, so the
code path below is the one that runs on the robot.
"""

from __future__ import annotations

import contextlib
import ctypes
import errno
import logging
import mmap
import os
import time

from ego.camera.source import GrantedFormat, PixelFormat, check_control_name
from ego.camera.v4l2_syscalls import LinuxSyscalls, V4L2Syscalls
from ego.camera.videodev2 import (
    BUF_FLAG_ERROR,
    BUF_TYPE_VIDEO_CAPTURE,
    CAP_DEVICE_CAPS,
    CAP_STREAMING,
    CAP_VIDEO_CAPTURE,
    CONTROL_IDS,
    CTRL_FLAG_DISABLED,
    FIELD_NONE,
    FOURCC,
    MEMORY_MMAP,
    VIDIOC_DQBUF,
    VIDIOC_G_CTRL,
    VIDIOC_QBUF,
    VIDIOC_QUERYBUF,
    VIDIOC_QUERYCAP,
    VIDIOC_QUERYCTRL,
    VIDIOC_REQBUFS,
    VIDIOC_S_CTRL,
    VIDIOC_S_FMT,
    VIDIOC_STREAMOFF,
    VIDIOC_STREAMON,
    IoctlArg,
    v4l2_buffer,
    v4l2_capability,
    v4l2_control,
    v4l2_format,
    v4l2_queryctrl,
    v4l2_requestbuffers,
)
from ego.errors import CameraCaptureError, CameraError, CameraTimeoutError, UnsupportedControlError

__all__ = [
    "DEFAULT_CAMERA_DEVICE",
    "V4L2Source",
]

#: The Overo's camera, unless EGO_CAMERA names another device (or "none").
DEFAULT_CAMERA_DEVICE = "/dev/video0"

log = logging.getLogger(__name__)

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
