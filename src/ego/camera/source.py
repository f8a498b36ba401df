"""Where raw frames come from: the FrameSource protocol, its vocabulary, and a file replay.

A :class:`~ego.camera.device.Camera` is given its source (``Camera(source=...)``): the
Overo's video device (:class:`~ego.camera.v4l2.V4L2Source`), the emulator's renderer
(``firmware_sim.camera.SimulatedSource``), or frames recorded to files
(:class:`FileReplaySource`). All of them hand over raw frames exactly as the sensor
lays them out; the camera converts and rotates.
"""

from __future__ import annotations

import errno
import os
from collections.abc import Iterable
from dataclasses import dataclass
from enum import Enum
from pathlib import Path
from typing import BinaryIO, Final, NamedTuple, Protocol, runtime_checkable

from ego.errors import CameraCaptureError, CameraError, UnsupportedControlError

__all__ = [
    "CONTROLS",
    "ControlRange",
    "FieldOfViewControl",
    "FileReplaySource",
    "FrameSource",
    "GrantedFormat",
    "PixelFormat",
    "check_control_name",
]


class PixelFormat(str, Enum):
    """How a raw frame's bytes encode its pixels (2 bytes a pixel in all three)."""

    #: RGB565 little-endian, V4L2 ``RGBP``: what the Overo's camera driver delivers.
    RGB565 = "RGB565"
    #: RGB565 big-endian, V4L2 ``RGBR``: what the e-puck's Bluetooth camera sends.
    RGB565_BE = "RGB565_BE"
    #: YUV 4:2:2 packed as Y0 U Y1 V, V4L2 ``YUYV``.
    YUYV = "YUYV"


class GrantedFormat(NamedTuple):
    """What a source agreed to deliver; the driver may adjust the size it was asked."""

    width: int
    height: int
    stride_bytes: int  # bytes from one row to the next (V4L2 bytesperline), >= 2 * width


@dataclass(frozen=True, slots=True)
class ControlRange:
    """The range ego accepts for a camera control (a device may narrow it: it clamps)."""

    minimum: int
    maximum: int
    thesis_default: int  # the value the thesis' configuration file starts from (C.2)


#: The thesis' camera controls (appendix C.2), by their ego name.
CONTROLS: Final[dict[str, ControlRange]] = {
    "brightness": ControlRange(0, 255, 1),
    "contrast": ControlRange(0, 255, 64),
    "saturation": ControlRange(0, 255, 64),
    "auto_white_balance": ControlRange(0, 1, 0),
}


def check_control_name(name: str) -> str:
    """``name`` if it is one of :data:`CONTROLS`, else :class:`UnsupportedControlError`."""
    if name not in CONTROLS:
        raise UnsupportedControlError(
            f"unknown camera control {name!r}; the controls are {', '.join(CONTROLS)}"
        )
    return name


class FrameSource(Protocol):
    """A supplier of raw frames; every method may raise a ``CameraError``."""

    def open(self, width: int, height: int, pixel_format: PixelFormat) -> GrantedFormat:
        """Start delivering frames, as near ``width`` x ``height`` as it can; again to resize."""
        ...

    def read_frame(self) -> bytes | bytearray | memoryview:
        """The next frame's bytes, ``stride_bytes * height`` long (valid until the next call)."""
        ...

    def set_control(self, name: str, value: int) -> int:
        """Set a control of :data:`CONTROLS` (source open); return the value it took."""
        ...

    def close(self) -> None:
        """Stop and release everything; safe to call twice."""
        ...


@runtime_checkable
class FieldOfViewControl(Protocol):
    """A source whose field of view can change (a renderer can zoom; real optics cannot)."""

    def set_fov_rad(self, fov_rad: float) -> float:
        """Use ``fov_rad`` horizontally from now on; return the value it took."""
        ...


class FileReplaySource:
    """Replays raw frames recorded to files, in order, looping by default.

    Each file holds one or more whole frames back to back (``stride_bytes * height``
    bytes each), as the sensor delivered them: RGB565 upside down for the e-puck.
    Recorded frames have one size, so ``open`` grants it whatever was asked (as a
    driver adjusts a size), but refuses another pixel format. Controls are accepted and
    reported as granted; they cannot change what was recorded.

    >>> source = FileReplaySource(["run1.raw"], width=160, height=120)  # doctest: +SKIP
    >>> camera = Camera(source=source)  # doctest: +SKIP
    """

    def __init__(
        self,
        paths: str | os.PathLike[str] | Iterable[str | os.PathLike[str]],
        width: int,
        height: int,
        pixel_format: PixelFormat = PixelFormat.RGB565,
        *,
        stride_bytes: int | None = None,
        loop: bool = True,
    ) -> None:
        if isinstance(paths, (str, os.PathLike)):
            paths = [paths]
        self.paths = [Path(p) for p in paths]
        if not self.paths:
            raise ValueError("FileReplaySource needs at least one file")
        self.width = width
        self.height = height
        self.pixel_format = PixelFormat(pixel_format)
        self.stride_bytes = 2 * width if stride_bytes is None else stride_bytes
        if self.stride_bytes < 2 * width:
            raise ValueError(f"stride {self.stride_bytes} is shorter than a {width}-pixel row")
        self.frame_bytes = self.stride_bytes * height
        self.loop = loop
        self._file: BinaryIO | None = None
        self._index = 0
        self._controls: dict[str, int] = {}

    def open(self, width: int, height: int, pixel_format: PixelFormat) -> GrantedFormat:
        if PixelFormat(pixel_format) is not self.pixel_format:
            raise CameraCaptureError(
                errno.EINVAL,
                f"the recorded frames are {self.pixel_format.value}, not {pixel_format}",
            )
        for path in self.paths:
            try:
                size = path.stat().st_size
            except OSError as exc:
                raise CameraCaptureError(exc.errno, f"cannot read frames from {path}") from exc
            if size == 0 or size % self.frame_bytes:
                raise CameraCaptureError(
                    errno.EINVAL,
                    f"{path} holds {size} bytes, not whole {self.frame_bytes}-byte frames "
                    f"({self.width}x{self.height}, stride {self.stride_bytes})",
                )
        self.close()
        self._index = 0
        return GrantedFormat(self.width, self.height, self.stride_bytes)

    def read_frame(self) -> bytes:
        for _ in range(len(self.paths) + 1):
            if self._file is None:
                if self._index >= len(self.paths):
                    if not self.loop:
                        raise CameraCaptureError(
                            errno.ENODATA, f"the replay of {len(self.paths)} file(s) is over"
                        )
                    self._index = 0
                self._file = self.paths[self._index].open("rb")
            frame = self._file.read(self.frame_bytes)
            if len(frame) == self.frame_bytes:
                return frame
            self._file.close()
            self._file = None
            self._index += 1
        raise CameraError("no frame could be read from the replay files")  # pragma: no cover

    def set_control(self, name: str, value: int) -> int:
        self._controls[check_control_name(name)] = value
        return value

    def close(self) -> None:
        if self._file is not None:
            self._file.close()
            self._file = None

    def __repr__(self) -> str:
        return (
            f"FileReplaySource({len(self.paths)} file(s), {self.width}x{self.height} "
            f"{self.pixel_format.value})"
        )
