"""A camera's V4L2 controls: kept until the source opens, applied to it then, refused when
out of their documented range (the device may still clamp within it, and the value it
took is what reads back)."""

from __future__ import annotations

from ego.camera.source import CONTROLS, FrameSource, GrantedFormat, check_control_name
from ego.errors import CameraError, OutOfRangeError
from ego.seam.validate import check_int

__all__ = ["CameraControls"]


class CameraControls:
    """The controls part of :class:`~ego.camera.Camera` (brightness, contrast...)."""

    name: str
    _source: FrameSource
    _granted: GrantedFormat | None
    _controls: dict[str, int]
    _closed: bool

    def _check_open(self) -> None:
        if self._closed:
            raise CameraError(f"{self.name} is closed")

    def _set_control(self, name: str, value: int) -> None:
        check_control_name(name)
        spec = CONTROLS[name]
        if not spec.minimum <= value <= spec.maximum:
            raise OutOfRangeError(f"{name} {value} is outside {spec.minimum}..{spec.maximum}")
        self._check_open()
        if self._granted is not None:
            value = self._source.set_control(name, value)
        self._controls[name] = value

    def get_control(self, name: str) -> int | None:
        """A control's value (as granted once applied), or None if never set."""
        return self._controls.get(check_control_name(name))

    def set_control(self, name: str, value: int) -> int:
        """Set a control of :data:`~ego.camera.source.CONTROLS` by name; return its value."""
        self._set_control(name, check_int(name, value, integral=True))
        return self._controls[name]

    @property
    def brightness(self) -> int | None:
        """Brightness, 0..255 (thesis default 1); None until set."""
        return self._controls.get("brightness")

    @brightness.setter
    def brightness(self, value: int) -> None:
        self._set_control("brightness", check_int("brightness", value, integral=True))

    @property
    def contrast(self) -> int | None:
        """Contrast, 0..255 (thesis default 64); None until set."""
        return self._controls.get("contrast")

    @contrast.setter
    def contrast(self, value: int) -> None:
        self._set_control("contrast", check_int("contrast", value, integral=True))

    @property
    def saturation(self) -> int | None:
        """Saturation, 0..255 (thesis default 64); None until set."""
        return self._controls.get("saturation")

    @saturation.setter
    def saturation(self, value: int) -> None:
        self._set_control("saturation", check_int("saturation", value, integral=True))

    @property
    def auto_white_balance(self) -> bool | None:
        """Automatic white balance on or off (thesis default off); None until set."""
        value = self._controls.get("auto_white_balance")
        return None if value is None else bool(value)

    @auto_white_balance.setter
    def auto_white_balance(self, value: bool) -> None:
        if value not in (True, False, 0, 1) or not isinstance(value, (bool, int)):
            raise TypeError(f"auto_white_balance must be True or False, not {value!r}")
        self._set_control("auto_white_balance", int(value))
