"""A camera's V4L2 controls: kept until the source opens, applied to it then, refused when
out of their documented range (the device may still clamp within it, and the value it
took is what reads back)."""

from __future__ import annotations

from typing import Protocol

from ego.camera.source import CONTROLS, FrameSource, GrantedFormat, check_control_name
from ego.errors import OutOfRangeError
from ego.seam.validate import check_int

__all__ = ["CameraControls", "Controlled"]


class Controlled(Protocol):
    """What the controls need of their camera: its source, whether it is open and the
    format it was granted, and where the values are kept."""

    @property
    def source(self: Controlled) -> FrameSource: ...

    @property
    def granted(self: Controlled) -> GrantedFormat | None: ...

    @property
    def control_values(self: Controlled) -> dict[str, int]: ...

    def check_open(self: Controlled) -> None: ...


def _set_control(camera: Controlled, name: str, value: int) -> None:
    check_control_name(name)
    spec = CONTROLS[name]
    if not spec.minimum <= value <= spec.maximum:
        raise OutOfRangeError(f"{name} {value} is outside {spec.minimum}..{spec.maximum}")
    camera.check_open()
    if camera.granted is not None:
        value = camera.source.set_control(name, value)
    camera.control_values[name] = value


class CameraControls:
    """The controls part of :class:`~ego.camera.Camera` (brightness, contrast...), over
    what :class:`Controlled` gives (its methods take that as their ``self`` type)."""

    def get_control(self: Controlled, name: str) -> int | None:
        """A control's value (as granted once applied), or None if never set."""
        return self.control_values.get(check_control_name(name))

    def set_control(self: Controlled, name: str, value: int) -> int:
        """Set a control of :data:`~ego.camera.source.CONTROLS` by name; return its value."""
        _set_control(self, name, check_int(name, value, integral=True))
        return self.control_values[name]

    @property
    def brightness(self: Controlled) -> int | None:
        """Brightness, 0..255 (thesis default 1); None until set."""
        return self.control_values.get("brightness")

    @brightness.setter
    def brightness(self: Controlled, value: int) -> None:
        _set_control(self, "brightness", check_int("brightness", value, integral=True))

    @property
    def contrast(self: Controlled) -> int | None:
        """Contrast, 0..255 (thesis default 64); None until set."""
        return self.control_values.get("contrast")

    @contrast.setter
    def contrast(self: Controlled, value: int) -> None:
        _set_control(self, "contrast", check_int("contrast", value, integral=True))

    @property
    def saturation(self: Controlled) -> int | None:
        """Saturation, 0..255 (thesis default 64); None until set."""
        return self.control_values.get("saturation")

    @saturation.setter
    def saturation(self: Controlled, value: int) -> None:
        _set_control(self, "saturation", check_int("saturation", value, integral=True))

    @property
    def auto_white_balance(self: Controlled) -> bool | None:
        """Automatic white balance on or off (thesis default off); None until set."""
        value = self.control_values.get("auto_white_balance")
        return None if value is None else bool(value)

    @auto_white_balance.setter
    def auto_white_balance(self: Controlled, value: bool) -> None:
        if value not in (True, False, 0, 1) or not isinstance(value, (bool, int)):
            raise TypeError(f"auto_white_balance must be True or False, not {value!r}")
        _set_control(self, "auto_white_balance", int(value))
