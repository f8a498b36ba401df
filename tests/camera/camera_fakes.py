"""Camera test doubles: an in-process V4L2 device behind the syscall seam, a scripted source.

``FakeVideoDevice`` implements ``ego.camera.v4l2_syscalls.V4L2Syscalls``. It is written from the
kernel's videodev2.h independently of ``ego.camera.videodev2``: it decodes each ioctl
request number (direction, size, type, number) and checks it against the literal
values of the kernel header for this word size, then reads and writes the argument's
raw bytes with ``struct`` at the header's offsets. A wrong ctypes layout in ego shows up
as wrong bytes here, not as a silently shared mistake. Buffers are real anonymous mmaps.
"""

from __future__ import annotations

import ctypes
import errno
import mmap
import struct
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from ego.camera import GrantedFormat, PixelFormat

WORD64 = struct.calcsize("P") == 8

# videodev2.h request numbers, as the kernel header expands them on this word size.
REQUESTS_64 = {
    "QUERYCAP": 0x80685600,
    "G_FMT": 0xC0D05604,
    "S_FMT": 0xC0D05605,
    "REQBUFS": 0xC0145608,
    "QUERYBUF": 0xC0585609,
    "QBUF": 0xC058560F,
    "DQBUF": 0xC0585611,
    "STREAMON": 0x40045612,
    "STREAMOFF": 0x40045613,
    "G_CTRL": 0xC008561B,
    "S_CTRL": 0xC008561C,
    "QUERYCTRL": 0xC0445624,
}
REQUESTS_32 = {
    **REQUESTS_64,
    "G_FMT": 0xC0CC5604,
    "S_FMT": 0xC0CC5605,
    "QUERYBUF": 0xC0445609,
    "QBUF": 0xC044560F,
    "DQBUF": 0xC0445611,
}
REQUESTS = REQUESTS_64 if WORD64 else REQUESTS_32
_BY_NUMBER = {number: name for name, number in REQUESTS.items()}

# Offsets in the kernel structs (videodev2.h) on this word size.
PIX = 8 if WORD64 else 4  # v4l2_format.fmt (the union has pointer alignment)
BUF = (
    {"timestamp": 24, "sequence": 56, "memory": 60, "m": 64, "length": 72}
    if WORD64
    else {"timestamp": 20, "sequence": 44, "memory": 48, "m": 52, "length": 56}
)
PAGE = mmap.PAGESIZE

CID_BRIGHTNESS, CID_CONTRAST, CID_SATURATION = 0x00980900, 0x00980901, 0x00980902
CID_AUTO_WHITE_BALANCE = 0x0098090C

FOURCCS = {"RGBP": PixelFormat.RGB565, "RGBR": PixelFormat.RGB565_BE, "YUYV": PixelFormat.YUYV}


def fourcc(code: str) -> int:
    return int.from_bytes(code.encode("ascii"), "little")


@dataclass
class FakeControl:
    minimum: int
    maximum: int
    step: int = 1
    default: int = 0
    kind: int = 1  # V4L2_CTRL_TYPE_INTEGER; 2 is BOOLEAN
    flags: int = 0
    value: int | None = None


def default_controls() -> dict[int, FakeControl]:
    return {
        CID_BRIGHTNESS: FakeControl(0, 127, default=1),
        CID_CONTRAST: FakeControl(0, 255, default=64),
        CID_SATURATION: FakeControl(0, 255, step=2, default=64),
        CID_AUTO_WHITE_BALANCE: FakeControl(0, 1, kind=2),
    }


def pattern_codes(sequence: int, width: int, height: int) -> np.ndarray:
    """Pseudo-random RGB565 codes, different for every pixel and frame, (height, width)."""
    codes = (np.arange(width * height, dtype=np.uint32) * 2654435761 + sequence * 40503) >> 7
    return codes.astype(np.uint16).reshape(height, width)


def pattern_frame(sequence: int, width: int, height: int, stride: int) -> bytes:
    """Frame ``sequence`` of ``pattern_codes``, little-endian, row padding filled with 0xEE."""
    rows = np.full((height, stride), 0xEE, dtype=np.uint8)
    codes = pattern_codes(sequence, width, height).astype("<u2")
    rows[:, : 2 * width] = codes.view(np.uint8).reshape(height, 2 * width)
    return rows.tobytes()


@dataclass
class _Buffer:
    length: int
    offset: int
    state: str = "user"  # user | queued | filled
    bytesused: int = 0
    sequence: int = 0
    flags: int = 0
    mapped: mmap.mmap | None = None


@dataclass
class FakeVideoDevice:
    """A capture device with the quirks real drivers have, each switchable by a test."""

    path: str = "/dev/video0"
    formats: tuple[str, ...] = ("RGBP", "YUYV")
    capabilities: int = 0x84000001  # DEVICE_CAPS | STREAMING | VIDEO_CAPTURE
    device_caps: int = 0x04000001
    width_align: int = 1  # granted widths are multiples of this (drivers round)
    height_align: int = 1
    stride_align: int = 1  # bytesperline rounded up to this (padded rows)
    max_buffers: int = 8  # REQBUFS grants at most this many
    controls: dict[int, FakeControl] = field(default_factory=default_controls)
    frame: Callable[[int, int, int, int], bytes] = pattern_frame
    busy: bool = False  # open() fails with EBUSY (another process has it)
    busy_format: bool = False  # S_FMT fails with EBUSY
    stalled: bool = False  # no frame ever arrives: select times out
    spurious_wakeups: int = 0  # select says ready, DQBUF then says EAGAIN, this many times
    corrupt_next: int = 0  # the next frames produced carry V4L2_BUF_FLAG_ERROR

    def __post_init__(self) -> None:
        self.calls: list[str] = []
        self.fds: set[int] = set()
        self.maps: list[mmap.mmap] = []
        self.buffers: list[_Buffer] = []
        self.queue: deque[int] = deque()  # queued buffers, in the order they were queued
        self.filled: deque[int] = deque()  # filled buffers, oldest first
        self.streaming = False
        self.sequence = 0
        self.width = self.height = self.stride = 0
        self.pixelformat = fourcc(self.formats[0])
        self._next_fd = 10

    # -- what tests look at ---------------------------------------------------------------

    @property
    def granted(self) -> GrantedFormat:
        return GrantedFormat(self.width, self.height, self.stride)

    def leaks(self) -> list[str]:
        found = [f"fd {fd} open" for fd in sorted(self.fds)]
        found += [f"mmap {i} not closed" for i, m in enumerate(self.maps) if not m.closed]
        if self.buffers:
            found.append(f"{len(self.buffers)} buffers not freed")
        return found

    def produce(self, count: int = 1) -> None:
        """Frames arrive: the oldest queued buffers are filled, in order."""
        for _ in range(count):
            if not self.queue:
                return
            index = self.queue.popleft()
            buf = self.buffers[index]
            data = self.frame(self.sequence, self.width, self.height, self.stride)
            assert buf.mapped is not None, "a buffer was queued without being mapped"
            buf.mapped[: len(data)] = data
            buf.state, buf.bytesused, buf.sequence = "filled", len(data), self.sequence
            buf.flags = 0x40 if self.corrupt_next > 0 else 0
            self.corrupt_next = max(0, self.corrupt_next - 1)
            self.sequence += 1
            self.filled.append(index)

    # -- the syscall seam ---------------------------------------------------------------------

    def open(self, path: str, flags: int) -> int:
        self.calls.append("open")
        if path != self.path:
            raise FileNotFoundError(errno.ENOENT, "No such file or directory", path)
        if self.busy:
            raise OSError(errno.EBUSY, "Device or resource busy", path)
        assert flags & 0o4000, "V4L2Source must open non-blocking (it selects, then dequeues)"
        fd = self._next_fd
        self._next_fd += 1
        self.fds.add(fd)
        return fd

    def close(self, fd: int) -> None:
        self.calls.append("close")
        self.fds.remove(fd)
        self.streaming = False  # the kernel stops and frees on the last close
        self.buffers = []
        self.queue.clear()
        self.filled.clear()

    def mmap(self, fd: int, length: int, offset: int) -> mmap.mmap:
        self.calls.append("mmap")
        assert fd in self.fds
        match = [b for b in self.buffers if b.offset == offset]
        if not match or match[0].length != length:
            raise OSError(errno.EINVAL, "Invalid argument")
        mapped = mmap.mmap(-1, length)  # a real anonymous mapping
        match[0].mapped = mapped
        self.maps.append(mapped)
        return mapped

    def select(self, fd: int, timeout_s: float) -> bool:
        self.calls.append("select")
        assert fd in self.fds and timeout_s > 0
        if not self.streaming or self.stalled:
            return False
        if self.filled or self.spurious_wakeups:
            return True
        self.produce(1)
        return bool(self.filled)

    def ioctl(self, fd: int, request: int, arg: ctypes.Structure | ctypes.c_int) -> None:
        assert fd in self.fds
        direction, size = request >> 30, (request >> 16) & 0x3FFF
        assert (request >> 8) & 0xFF == ord("V"), f"not a V4L2 request: {request:#x}"
        name = _BY_NUMBER.get(request)
        if name is None:
            raise OSError(errno.ENOTTY, f"unknown ioctl {request:#x}")
        raw = (ctypes.c_uint8 * ctypes.sizeof(arg)).from_buffer(arg)
        assert len(raw) == size, f"{name}: argument is {len(raw)} bytes, request says {size}"
        assert direction == (2 if name == "QUERYCAP" else 1 if "STREAM" in name else 3)
        self.calls.append(name)
        getattr(self, f"_{name.lower()}")(memoryview(raw).cast("B"))

    # -- the ioctls, on raw bytes --------------------------------------------------------------

    def _querycap(self, b: memoryview) -> None:
        struct.pack_into(
            "16s32s32sIII",
            b,
            0,
            b"fakecam",
            b"Fake e-puck camera",
            b"platform:fake",
            0x060000,
            self.capabilities,
            self.device_caps,
        )

    def _s_fmt(self, b: memoryview) -> None:
        (kind,) = struct.unpack_from("I", b, 0)
        width, height, pixelformat, _field = struct.unpack_from("4I", b, PIX)
        if kind != 1:
            raise OSError(errno.EINVAL, "not a capture format")
        if self.busy_format or self.streaming:
            raise OSError(errno.EBUSY, "Device or resource busy")
        if pixelformat not in {fourcc(f) for f in self.formats}:
            pixelformat = fourcc(self.formats[0])  # drivers substitute, they do not refuse
        width = max(32, min(640, width)) // self.width_align * self.width_align
        height = max(32, min(480, height)) // self.height_align * self.height_align
        stride = -(-2 * width // self.stride_align) * self.stride_align
        self.width, self.height, self.stride, self.pixelformat = width, height, stride, pixelformat
        struct.pack_into("6I", b, PIX, width, height, pixelformat, 1, stride, stride * height)

    def _g_fmt(self, b: memoryview) -> None:  # pragma: no cover - ego does not need it
        struct.pack_into(
            "6I",
            b,
            PIX,
            self.width,
            self.height,
            self.pixelformat,
            1,
            self.stride,
            self.stride * self.height,
        )

    def _reqbufs(self, b: memoryview) -> None:
        count, kind, memory = struct.unpack_from("3I", b, 0)
        if kind != 1 or memory != 1:
            raise OSError(errno.EINVAL, "capture + mmap only")
        if self.streaming:
            raise OSError(errno.EBUSY, "Device or resource busy")
        granted = min(count, self.max_buffers)
        length = -(-self.stride * self.height // PAGE) * PAGE
        self.buffers = [_Buffer(length, i * length) for i in range(granted)]
        self.queue.clear()
        self.filled.clear()
        struct.pack_into("I", b, 0, granted)

    def _buffer(self, b: memoryview) -> _Buffer:
        index, kind = struct.unpack_from("2I", b, 0)
        (memory,) = struct.unpack_from("I", b, BUF["memory"])
        if kind != 1 or memory != 1 or index >= len(self.buffers):
            raise OSError(errno.EINVAL, "Invalid argument")
        return self.buffers[index]

    def _describe(self, b: memoryview, index: int) -> None:
        buf = self.buffers[index]
        struct.pack_into("5I", b, 0, index, 1, buf.bytesused, buf.flags, 1)
        struct.pack_into("I", b, BUF["sequence"], buf.sequence)
        struct.pack_into("I", b, BUF["m"], buf.offset)
        struct.pack_into("I", b, BUF["length"], buf.length)

    def _querybuf(self, b: memoryview) -> None:
        buf = self._buffer(b)
        self._describe(b, self.buffers.index(buf))

    def _qbuf(self, b: memoryview) -> None:
        buf = self._buffer(b)
        if buf.state != "user":
            raise OSError(errno.EINVAL, "buffer already queued")
        buf.state = "queued"
        self.queue.append(self.buffers.index(buf))

    def _dqbuf(self, b: memoryview) -> None:
        index, kind = struct.unpack_from("2I", b, 0)
        if kind != 1 or not self.streaming:
            raise OSError(errno.EINVAL, "not streaming")
        if self.spurious_wakeups:
            self.spurious_wakeups -= 1
            raise BlockingIOError(errno.EAGAIN, "Resource temporarily unavailable")
        if not self.filled:
            raise BlockingIOError(errno.EAGAIN, "Resource temporarily unavailable")
        index = self.filled.popleft()
        self.buffers[index].state = "user"
        self._describe(b, index)

    def _streamon(self, b: memoryview) -> None:
        (kind,) = struct.unpack_from("i", b, 0)
        if kind != 1 or not self.buffers:
            raise OSError(errno.EINVAL, "no buffers")
        self.streaming = True

    def _streamoff(self, b: memoryview) -> None:
        (kind,) = struct.unpack_from("i", b, 0)
        if kind != 1:
            raise OSError(errno.EINVAL, "Invalid argument")
        self.streaming = False
        self.queue.clear()
        self.filled.clear()
        for buf in self.buffers:
            buf.state = "user"

    def _queryctrl(self, b: memoryview) -> None:
        (cid,) = struct.unpack_from("I", b, 0)
        ctrl = self.controls.get(cid)
        if ctrl is None:
            raise OSError(errno.EINVAL, "no such control")
        struct.pack_into(
            "II32s5i",
            b,
            0,
            cid,
            ctrl.kind,
            b"control",
            ctrl.minimum,
            ctrl.maximum,
            ctrl.step,
            ctrl.default,
            ctrl.flags,
        )

    def _s_ctrl(self, b: memoryview) -> None:
        cid, value = struct.unpack_from("Ii", b, 0)
        ctrl = self.controls.get(cid)
        if ctrl is None:
            raise OSError(errno.EINVAL, "no such control")
        if not ctrl.minimum <= value <= ctrl.maximum:
            raise OSError(errno.ERANGE, "Numerical result out of range")
        ctrl.value = value

    def _g_ctrl(self, b: memoryview) -> None:
        (cid,) = struct.unpack_from("I", b, 0)
        ctrl = self.controls.get(cid)
        if ctrl is None:
            raise OSError(errno.EINVAL, "no such control")
        struct.pack_into("i", b, 4, ctrl.default if ctrl.value is None else ctrl.value)


class ScriptedSource:
    """A FrameSource that hands out given frames and records what it was asked."""

    def __init__(
        self,
        frames: list[bytes] | None = None,
        *,
        grant: tuple[int, int] | None = None,
        pixel_format_ok: bool = True,
    ) -> None:
        self.frames = frames
        self.grant = grant
        self.pixel_format_ok = pixel_format_ok
        self.opened: list[tuple[int, int, PixelFormat]] = []
        self.controls: list[tuple[str, int]] = []
        self.reads = 0
        self.closes = 0
        self.format: GrantedFormat | None = None

    def open(self, width: int, height: int, pixel_format: PixelFormat) -> GrantedFormat:
        self.opened.append((width, height, pixel_format))
        w, h = self.grant or (width, height)
        self.format = GrantedFormat(w, h, 2 * w)
        return self.format

    def read_frame(self) -> bytes:
        assert self.format is not None
        self.reads += 1
        if self.frames:
            return self.frames[(self.reads - 1) % len(self.frames)]
        return pattern_frame(
            self.reads - 1, self.format.width, self.format.height, self.format.stride_bytes
        )

    def set_control(self, name: str, value: int) -> int:
        self.controls.append((name, value))
        return min(value, 100)  # this "driver" tops out at 100

    def close(self) -> None:
        self.closes += 1


# -- a stand-in world with just the attributes the renderer may use ---------------------------


@dataclass
class StandInPose:
    x_m: float = 0.0
    y_m: float = 0.0
    theta_rad: float = 0.0


@dataclass
class StandInArena:
    half_size_m: float = 0.5
    wall_rgb: tuple[int, int, int] = (200, 190, 170)


@dataclass
class StandInLamp:
    x_m: float = 0.4
    y_m: float = 0.4


@dataclass
class StandInBlock:
    x_m: float
    y_m: float
    half_size_m: float
    rgb: tuple[int, int, int]


@dataclass
class StandInWorld:
    pose: StandInPose = field(default_factory=StandInPose)
    arena: StandInArena = field(default_factory=StandInArena)
    lamp: StandInLamp = field(default_factory=StandInLamp)
    blocks: list[StandInBlock] = field(default_factory=list)

    def snapshot(self) -> StandInPose:
        return self.pose
