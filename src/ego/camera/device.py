"""The e-puck camera as a device: sampling, conversion, controls, configuration, pixels."""

from __future__ import annotations

import logging
import math
import os
from enum import Enum
from types import TracebackType
from typing import Final, TypeVar

import numpy as np
import numpy.typing as npt

from ego.camera.config import apply_configuration, size_range
from ego.camera.controls import CameraControls
from ego.camera.convert import (
    YuvFormula,
    check_rotation,
)
from ego.camera.frames import frame_to_rgb888
from ego.camera.pixels import BgraCopy, PixelReads
from ego.camera.sampling import SamplingSchedule
from ego.camera.source import (
    FieldOfViewControl,
    FrameSource,
    GrantedFormat,
    PixelFormat,
)
from ego.errors import CameraError, OutOfRangeError
from ego.seam.validate import check_int

__all__ = ["DEFAULT_FOV_RAD", "Camera"]

log = logging.getLogger(__name__)

#: The e-puck camera's horizontal field of view (Webots' e-puck model), radians.
DEFAULT_FOV_RAD: Final = 0.84

Image = npt.NDArray[np.uint8]


_E = TypeVar("_E", bound=Enum)


def _choice(what: str, kind: type[_E], value: object) -> _E:
    """``value`` as a member of ``kind``, else OutOfRangeError naming the choices."""
    try:
        return kind(value)
    except ValueError:
        choices = ", ".join(str(member.value) for member in kind)
        raise OutOfRangeError(f"{what} {value!r} is not one of {choices}") from None


def check_fov(fov_rad: float) -> float:
    if isinstance(fov_rad, bool) or not isinstance(fov_rad, (int, float)):
        raise TypeError(f"fov_rad must be a number, not {fov_rad!r}")
    if not 0.0 < fov_rad < math.pi:
        raise OutOfRangeError(f"field of view {fov_rad} rad is outside (0, pi)")
    return float(fov_rad)


def sensor_size_for(width: int, height: int, rotation: int) -> tuple[int, int]:
    """The sensor's (width, height) for an image of ``width`` x ``height``."""
    width, height = (
        check_int("width", width, integral=True),
        check_int("height", height, integral=True),
    )
    low, high = size_range(rotation)
    if not (low[0] <= width <= high[0] and low[1] <= height <= high[1]):
        turned = f" at rotation {rotation}" if rotation in (90, 270) else ""
        raise OutOfRangeError(
            f"camera size {width}x{height} is outside "
            f"{low[0]}x{low[1]}..{high[0]}x{high[1]}{turned}"
        )
    return (height, width) if rotation in (90, 270) else (width, height)


class Camera(CameraControls, PixelReads):
    """The camera: a frame source, converted to RGB888 and rotated each time it is due.

    The image is delivered upright by default (``rotation=180`` undoes the upside-down
    mounting). Sizes are the image's (after rotation); the sensor takes 32x32..640x480.
    Controls (:class:`~ego.camera.controls.CameraControls`) outside their documented range
    are refused; inside it, the device may still clamp, and the property reports what it
    took. Those set before the source opens are applied when it does.

    ``image`` is refreshed in place by each capture (no allocation per frame, as the
    thesis' pointer and Webots' getImage): copy it to keep a frame.

    >>> from firmware_sim.camera import SimulatedSource
    >>> source = SimulatedSource(world)  # or V4L2Source("/dev/video0")  # doctest: +SKIP
    >>> with Camera(source=source, width=160, height=120) as camera:  # doctest: +SKIP
    ...     camera.enable(64)
    ...     camera.update(now_ms=0)  # the scheduler does this every step
    ...     red = camera.get_red(80, 60)
    """

    def __init__(
        self,
        source: FrameSource | None = None,
        *,
        width: int = 640,
        height: int = 480,
        rotation: int = 180,
        pixel_format: PixelFormat = PixelFormat.RGB565,
        yuv_formula: YuvFormula = YuvFormula.ITU_R_INTEGER,
        fov_rad: float = DEFAULT_FOV_RAD,
        name: str = "camera",
    ) -> None:
        if source is None:
            from ego.camera.v4l2 import V4L2Source

            source = V4L2Source()
        self.name = name
        self._source: FrameSource = source
        self._pixel_format = _choice("pixel format", PixelFormat, pixel_format)
        self.yuv_formula = _choice("YUV formula", YuvFormula, yuv_formula)
        self._rotation = check_rotation(rotation)
        self._sensor = sensor_size_for(width, height, self._rotation)
        self._fov_rad = check_fov(fov_rad)
        self._granted: GrantedFormat | None = None
        self._controls: dict[str, int] = {}  # requested, or granted once applied
        self._schedule = SamplingSchedule()
        self._rgb: Image | None = None
        self._bgra = BgraCopy()
        self._frames = 0
        self._closed = False

    # -- the source ------------------------------------------------------------------------

    def _open_source(self) -> None:
        """(Re)open the source at the sensor size, then apply the controls set so far."""
        self.check_open()
        asked_w, asked_h = self._sensor
        granted = self._source.open(asked_w, asked_h, self._pixel_format)
        if (granted.width, granted.height) != (asked_w, asked_h):
            log.info("%s: asked %dx%d, the source granted %dx%d",
                     self.name, asked_w, asked_h, granted.width, granted.height)  # fmt: skip
        self._granted = granted
        self._sensor = (granted.width, granted.height)
        self._rgb = None
        for control, value in list(self._controls.items()):
            self._controls[control] = self._source.set_control(control, value)

    def enable(self, period_ms: int) -> None:
        """Capture a frame every ``period_ms`` ms (> 0); opens the source on first use."""
        period_ms = self._schedule.checked(period_ms)
        if self._granted is None:
            self._open_source()
        self.check_open()
        self._schedule.start(period_ms)

    def disable(self) -> None:
        """Stop sampling (the source stays open: enabling again is quick)."""
        self._schedule.stop()

    @property
    def sampling_period(self) -> int | None:
        """The sampling period in ms, or ``None`` when disabled."""
        return self._schedule.period_ms

    def is_due(self, now_ms: float) -> bool:
        """Whether ``update(now_ms)`` would capture a frame."""
        return not self._closed and self._schedule.is_due(now_ms)

    def update(self, now_ms: float) -> bool:
        """Capture and convert a frame if one is due at ``now_ms`` (the step clock's time);
        True if it did (:class:`~ego.camera.sampling.SamplingSchedule`)."""
        if not self.is_due(now_ms):
            return False
        self.capture()
        self._schedule.taken(now_ms)
        return True

    @property
    def source(self) -> FrameSource:
        """Where the frames come from."""
        return self._source

    @property
    def granted(self) -> GrantedFormat | None:
        """What the source granted when it opened; None until it did."""
        return self._granted

    @property
    def control_values(self) -> dict[str, int]:
        """The controls set, by name: as asked until the source opens, as granted after."""
        return self._controls

    def check_open(self) -> None:
        if self._closed:  # CameraError once closed
            raise CameraError(f"{self.name} is closed")

    @property
    def pixel_format(self) -> PixelFormat:
        """The raw frame format asked of the source."""
        return self._pixel_format

    def capture(self) -> Image:
        """Read one frame from the source now (schedule aside) and convert it."""
        self.check_open()
        if self._granted is None:
            self._open_source()
        granted = self._granted
        assert granted is not None
        raw = self._source.read_frame()
        ih, iw = self._image_shape()
        if self._rgb is None or self._rgb.shape != (ih, iw, 3):
            self._rgb = np.empty((ih, iw, 3), dtype=np.uint8)
        frame_to_rgb888(
            raw, granted, self._pixel_format, self._rotation, self.yuv_formula, out=self._rgb
        )
        del raw  # the source may reuse the buffer once we let go
        self._frames += 1
        return self.image

    # -- the image -----------------------------------------------------------------------------

    def _image_shape(self) -> tuple[int, int]:
        w, h = self._sensor
        return (w, h) if self._rotation in (90, 270) else (h, w)

    @property
    def image(self) -> Image:
        """The last frame, RGB888 ``(height, width, 3)`` uint8, read-only, refreshed in place."""
        if self._rgb is None or self._frames == 0:
            state = "is not enabled" if self.sampling_period is None else "has no frame yet"
            raise CameraError(f"{self.name} {state}: enable(period_ms) it, then step")
        view = self._rgb.view()
        view.flags.writeable = False
        return view

    @property
    def bgra_copy(self) -> BgraCopy:
        return self._bgra  # the last frame's BGRA copy (image_bgra)

    @property
    def frame_count(self) -> int:
        """How many frames have been captured."""
        return self._frames

    @property
    def width(self) -> int:
        """Width of the image in pixels (after rotation; as granted by the source)."""
        return self._image_shape()[1]

    @property
    def height(self) -> int:
        """Height of the image in pixels (after rotation; as granted by the source)."""
        return self._image_shape()[0]

    @property
    def sensor_size(self) -> tuple[int, int]:
        """(width, height) of the sensor's frames, before rotation."""
        return self._sensor

    def set_size(self, width: int, height: int) -> tuple[int, int]:
        """Ask for an image of ``width`` x ``height``; return the (width, height) granted.

        Ranges: 32x32..640x480, or 32x32..480x640 at rotation 90/270 (OutOfRangeError).
        The source (the driver) may adjust it: the granted size is returned and becomes
        ``width``/``height``.
        """
        sensor = sensor_size_for(width, height, self._rotation)
        self.check_open()
        self._sensor = sensor
        if self._granted is not None:
            self._open_source()
        return self.width, self.height

    @property
    def rotation(self) -> int:
        """Degrees counter-clockwise applied to the sensor's frames: 0, 90, 180 (default:
        undoes the upside-down mounting), 270; 90 and 270 swap ``width`` and ``height``."""
        return self._rotation

    @rotation.setter
    def rotation(self, rotation: int) -> None:
        self._rotation = check_rotation(rotation)

    @property
    def fov_rad(self) -> float:
        """Horizontal field of view in radians (0 < fov < pi)."""
        return self._fov_rad

    @fov_rad.setter
    def fov_rad(self, fov_rad: float) -> None:
        fov_rad = check_fov(fov_rad)
        if isinstance(self._source, FieldOfViewControl):  # a renderer can zoom
            fov_rad = self._source.set_fov_rad(fov_rad)
        self._fov_rad = fov_rad

    def load_configuration(self, path: str | os.PathLike[str]) -> None:
        """Apply a camera configuration file (:func:`ego.camera.config.apply_configuration`)."""
        apply_configuration(self, path)

    # -- lifetime --------------------------------------------------------------------------------

    def close(self) -> None:
        """Stop sampling and close the source; safe to call twice."""
        if self._closed:
            return
        self._closed = True
        self._schedule.stop()
        self._source.close()

    def __enter__(self) -> Camera:
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        self.close()

    def __repr__(self) -> str:
        period_ms = self.sampling_period
        period = "disabled" if period_ms is None else f"every {period_ms} ms"
        state = "closed" if self._closed else period
        return (
            f"<Camera {self.name!r} {self.width}x{self.height} rotation {self._rotation} "
            f"{self._pixel_format.value}, {state}, {self._frames} frames>"
        )
