"""Integer device tags, as ``wb_robot_get_device`` returns them, for the C-style faces.

The tag of a name is fixed (its place in :data:`DEVICE_NAMES`, from 1), so ``ego.webots``
and ``ego.overo`` agree on it; 0 is never a valid tag, as in Webots.
"""

from __future__ import annotations

from ego.errors import UnknownDeviceError

__all__ = ["DEVICE_NAMES", "name_of", "tag_of"]

DEVICE_NAMES: tuple[str, ...] = (
    *(f"ps{i}" for i in range(10)),
    *(f"gs{i}" for i in range(3)),
    *(f"ls{i}" for i in range(8)),
    "accelerometer",
    "left wheel motor",
    "right wheel motor",
    "left wheel sensor",
    "right wheel sensor",
    *(f"led{i}" for i in range(10)),
    *(f"mic{i}" for i in range(3)),
    "camera",
)
_TAGS = {name: i + 1 for i, name in enumerate(DEVICE_NAMES)}


def tag_of(name: str) -> int:
    try:
        return _TAGS[name]
    except KeyError:
        raise UnknownDeviceError(
            f"no device named {name!r}; valid names: {', '.join(DEVICE_NAMES)}"
        ) from None


def name_of(tag: int | str) -> str:
    """The device name of a tag, or of a name (checked)."""
    if isinstance(tag, str):
        tag_of(tag)
        return tag
    if isinstance(tag, bool) or not isinstance(tag, int) or not 1 <= tag <= len(DEVICE_NAMES):
        raise UnknownDeviceError(
            f"device tag {tag!r} is not one of 1..{len(DEVICE_NAMES)} "
            "(the tags wb_robot_get_device returns)"
        )
    return DEVICE_NAMES[tag - 1]
