"""The camera's own refinements of ``ego.errors.CameraError`` (to be folded into ego/errors.py).

::

    CameraError                                   (ego.errors)
    ├── CameraConfigError (ValueError)            (ego.errors)
    │   ├── ConfigSyntaxError                     not ``key = value``, or a bad value
    │   ├── UnknownSettingError                   a key the camera does not have
    │   └── SettingOutOfRangeError (OutOfRangeError)  a value outside the key's range
    ├── CameraCaptureError (OSError)              (ego.errors) the video device refused or failed
    │   └── CameraTimeoutError (TimeoutError)     no frame arrived within the timeout
    ├── UnsupportedControlError (KeyError)        an unknown control, or one the device lacks
    ├── FrameSizeError (ValueError)               a raw buffer too short for the frame geometry
    └── ImageFormatError (ValueError)             a file extension neither JPEG nor PNG

Every configuration error carries ``path`` and ``line_number`` (1-based), and its message
starts with ``path:line:`` so that an editor can jump to it.
"""

from __future__ import annotations

from ego.errors import (
    CameraCaptureError,
    CameraConfigError,
    CameraError,
    OutOfRangeError,
)

__all__ = [
    "CameraTimeoutError",
    "ConfigSyntaxError",
    "FrameSizeError",
    "ImageFormatError",
    "SettingOutOfRangeError",
    "UnknownSettingError",
    "UnsupportedControlError",
]


class _LocatedConfigError(CameraConfigError):
    """A configuration error tied to one line of one file."""

    def __init__(self, path: str, line_number: int, message: str) -> None:
        super().__init__(f"{path}:{line_number}: {message}")
        self.path = path
        self.line_number = line_number


class ConfigSyntaxError(_LocatedConfigError):
    """A line that is not ``key = value``, a repeated key, or a value of the wrong type."""


class UnknownSettingError(_LocatedConfigError):
    """A key the camera does not have; the message lists the keys that exist."""


class SettingOutOfRangeError(_LocatedConfigError, OutOfRangeError):
    """A value outside the range of its key; the message names the range."""


class CameraTimeoutError(CameraCaptureError, TimeoutError):
    """No frame arrived from the video device within the timeout."""


class UnsupportedControlError(CameraError, KeyError):
    """A control (brightness, contrast...) that is unknown or that the device does not offer."""

    def __str__(self) -> str:  # KeyError would quote the whole message
        return str(self.args[0]) if self.args else ""


class FrameSizeError(CameraError, ValueError):
    """A raw frame buffer too short for its width, height and row stride."""


class ImageFormatError(CameraError, ValueError):
    """A file name whose extension names no supported image format (.jpg, .jpeg, .png)."""
