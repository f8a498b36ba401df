"""The camera configuration file (thesis C.2: the camera parameters read at start).

The thesis' ``overo_camera_extract_parameters_from_configuration_file`` loads the
camera's resolution, brightness, contrast, saturation and auto white balance from a
file. ego's format is one ``key = value`` per line::

    # e-puck camera, as E-GO starts it
    width = 640                # pixels of the image you get (32..640, or 32..480 at 90/270)
    height = 480               # (32..480, or 32..640 when rotated by 90 or 270)
    rotation = 180             # degrees counter-clockwise applied to the sensor's frame
    fov_rad = 0.84             # horizontal field of view, 0 < fov < pi
    brightness = 1             # 0..255
    contrast = 64              # 0..255
    saturation = 64            # 0..255
    auto_white_balance = off   # on/off, true/false, yes/no, 1/0

- ``#`` starts a comment, anywhere on a line; blank lines are ignored.
- Keys are lower case, each at most once; every key is optional (absent keys leave the
  camera as it is).
- Integers are decimal (ASCII digits, an optional sign); ``fov_rad`` is a decimal number
  (``0.84``, ``8.4e-1``).
- ``width``/``height`` are the image's size after rotation, so they are checked against
  the ranges of the file's ``rotation`` (or, when the file has none, the camera's).

Each problem raises a typed error carrying ``path`` and ``line_number`` and a message
that starts ``path:line:``: :class:`ConfigSyntaxError` (no ``=``, no key or value, a
value of the wrong type, a repeated key), :class:`UnknownSettingError` (listing the
keys), :class:`SettingOutOfRangeError` (naming the range). Nothing is applied unless the
whole file is valid. The file itself must be a regular file of at most
:data:`MAX_CONFIG_BYTES` (a FIFO or ``/dev/zero`` is refused, not read): else a
:class:`CameraConfigError` naming it and the reason.
"""

from __future__ import annotations

import math
import os
import re
from dataclasses import dataclass, fields
from pathlib import Path
from typing import Final, Protocol

from ego.camera.convert import ROTATIONS
from ego.camera.source import CONTROLS
from ego.errors import (
    BadFileError,
    CameraConfigError,
    ConfigSyntaxError,
    SettingOutOfRangeError,
    UnknownSettingError,
)
from ego.seam.files import read_regular

__all__ = [
    "MAX_CONFIG_BYTES",
    "MAX_SIZE",
    "MIN_SIZE",
    "CameraConfiguration",
    "apply_configuration",
    "parse_configuration",
    "read_configuration",
    "size_range",
]

#: The sensor's smallest and largest frame, (width, height) as it is mounted (thesis C.2).
MIN_SIZE: Final = (32, 32)
MAX_SIZE: Final = (640, 480)

#: A configuration file's size, at most (eight settings and their comments fit in 1 KiB).
MAX_CONFIG_BYTES = 64 << 10

_TRUE = {"1", "on", "true", "yes"}
_FALSE = {"0", "off", "false", "no"}


def size_range(rotation: int) -> tuple[tuple[int, int], tuple[int, int]]:
    """The smallest and largest image (width, height) at ``rotation``."""
    if rotation in (90, 270):
        return (MIN_SIZE[1], MIN_SIZE[0]), (MAX_SIZE[1], MAX_SIZE[0])
    return MIN_SIZE, MAX_SIZE


@dataclass(frozen=True, slots=True)
class CameraConfiguration:
    """The settings a configuration file gives; ``None`` where the file says nothing."""

    width: int | None = None
    height: int | None = None
    rotation: int | None = None
    fov_rad: float | None = None
    brightness: int | None = None
    contrast: int | None = None
    saturation: int | None = None
    auto_white_balance: bool | None = None

    def controls(self) -> dict[str, int]:
        """The device controls the file sets, by name, booleans as 0/1."""
        return {name: int(value) for name in CONTROLS if (value := getattr(self, name)) is not None}


KEYS: Final = tuple(f.name for f in fields(CameraConfiguration))


#: Plain ASCII decimals only: int() and float() also take "6_40", full-width digits,
#: "nan" or "inf", which no camera file means.
_INTEGER = re.compile(r"[+-]?[0-9]+")
_DECIMAL = re.compile(r"[+-]?([0-9]+\.?[0-9]*|\.[0-9]+)([eE][+-]?[0-9]+)?")


#: No setting needs more digits; Python refuses to convert past 4300 anyway.
MAX_DIGITS = 12


def _parse_int(path: str, number: int, key: str, text: str) -> int:
    if not _INTEGER.fullmatch(text):
        raise ConfigSyntaxError(path, number, f"{key} must be an integer, not {text!r}")
    if len(text.lstrip("+-")) > MAX_DIGITS:
        raise SettingOutOfRangeError(
            path, number, f"{key} {text[:12]}... ({len(text)} digits) is far out of range"
        )
    return int(text)


def parse_configuration(
    text: str, path: str = "<string>", *, current_rotation: int = 180
) -> CameraConfiguration:
    """Parse a configuration file's text (format in the module docstring)."""
    values: dict[str, object] = {}
    lines: dict[str, int] = {}
    for number, raw in enumerate(text.splitlines(), start=1):
        line = raw.split("#", 1)[0].strip()
        if not line:
            continue
        key, equals, value = (part.strip() for part in line.partition("="))
        if not equals:
            raise ConfigSyntaxError(path, number, f"expected 'key = value', got {line!r}")
        if not key:
            raise ConfigSyntaxError(path, number, f"missing key before '=' in {line!r}")
        if key not in KEYS:
            raise UnknownSettingError(
                path, number, f"unknown setting {key!r}; the settings are {', '.join(KEYS)}"
            )
        if not value:
            raise ConfigSyntaxError(path, number, f"missing value for {key}")
        if key in lines:
            raise ConfigSyntaxError(
                path, number, f"{key} is set twice (first on line {lines[key]})"
            )
        lines[key] = number
        values[key] = _parse_value(path, number, key, value)
    rotation = values.get("rotation", current_rotation)
    assert isinstance(rotation, int)
    _check_size(path, values, lines, rotation)
    return CameraConfiguration(**values)  # type: ignore[arg-type]


def _parse_value(path: str, number: int, key: str, value: str) -> object:
    """The value of ``key = value`` on line ``number``, checked against the key's range."""
    if key == "auto_white_balance":
        lowered = value.lower()
        if lowered not in _TRUE | _FALSE:
            raise ConfigSyntaxError(
                path, number, f"auto_white_balance must be on or off, not {value!r}"
            )
        return lowered in _TRUE
    if key == "fov_rad":
        if not _DECIMAL.fullmatch(value) or len(value) > 32:
            raise ConfigSyntaxError(path, number, f"fov_rad must be a number, not {value!r}")
        fov = float(value)
        if not 0.0 < fov < math.pi:
            raise SettingOutOfRangeError(path, number, f"fov_rad {value} is outside (0, pi)")
        return fov
    parsed = _parse_int(path, number, key, value)
    if key == "rotation" and parsed not in ROTATIONS:
        raise SettingOutOfRangeError(
            path, number, f"rotation {parsed} is not one of 0, 90, 180, 270"
        )
    if key in CONTROLS:
        spec = CONTROLS[key]
        if not spec.minimum <= parsed <= spec.maximum:
            raise SettingOutOfRangeError(
                path, number, f"{key} {parsed} is outside {spec.minimum}..{spec.maximum}"
            )
    return parsed


def _check_size(path: str, values: dict[str, object], lines: dict[str, int], rotation: int) -> None:
    """The width and height the file gives, within the sizes served at ``rotation``."""
    low, high = size_range(rotation)
    for axis, key in enumerate(("width", "height")):
        size = values.get(key)
        if size is not None and not low[axis] <= size <= high[axis]:  # type: ignore[operator]
            raise SettingOutOfRangeError(
                path,
                lines[key],
                f"{key} {size} is outside {low[axis]}..{high[axis]} at rotation {rotation}",
            )


def read_configuration(
    path: str | os.PathLike[str], *, current_rotation: int = 180
) -> CameraConfiguration:
    """Read and parse a configuration file (``OSError`` if it cannot be read)."""
    file = Path(path)
    try:
        data = read_regular(file, MAX_CONFIG_BYTES, "a camera configuration")
    except BadFileError as exc:
        raise CameraConfigError(str(exc)) from exc
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = data[: exc.start].count(b"\n") + 1
        raise ConfigSyntaxError(
            str(file), line, f"byte 0x{data[exc.start]:02x} is not UTF-8 text"
        ) from exc
    return parse_configuration(text, str(file), current_rotation=current_rotation)


class Configurable(Protocol):
    """What a configuration file sets: a :class:`~ego.camera.Camera` is one (described
    here, not imported, so that the camera may import this module)."""

    rotation: int
    fov_rad: float

    @property
    def width(self) -> int: ...

    @property
    def height(self) -> int: ...

    def set_size(self, width: int, height: int) -> object: ...

    def set_control(self, name: str, value: int) -> object: ...


def apply_configuration(camera: Configurable, path: str | os.PathLike[str]) -> None:
    """Apply a configuration file to ``camera``.

    The file is checked whole before anything changes; its typed errors give the line. A
    device that lacks a control the file sets raises UnsupportedControlError after the
    settings before it were applied.
    """
    config = read_configuration(path, current_rotation=camera.rotation)
    if config.rotation is not None:
        camera.rotation = config.rotation
    if config.fov_rad is not None:
        camera.fov_rad = config.fov_rad
    if config.width is not None or config.height is not None:
        camera.set_size(config.width or camera.width, config.height or camera.height)
    for name, value in config.controls().items():
        camera.set_control(name, value)
