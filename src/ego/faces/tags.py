"""Integer device tags, as ``wb_robot_get_device`` returns them, for the C-style faces.

The tag of a name is fixed (its row's place in :mod:`ego.devices.table`, from 1), so
``ego.webots`` and ``ego.overo`` agree on it; 0 is never a valid tag, as in Webots. This
module is the table's C-style alias.
"""

from __future__ import annotations

from ego.devices.table import DEVICES, find, spec_of_tag
from ego.errors import UnknownDeviceError

__all__ = ["DEVICE_NAMES", "name_of", "tag_of"]

#: The names of the devices with a tag, in tag order (from :data:`ego.devices.table.DEVICES`).
DEVICE_NAMES: tuple[str, ...] = tuple(s.name for s in DEVICES)


def tag_of(name: str) -> int:
    found = find(name)
    if found is None or found.tag is None:
        raise UnknownDeviceError(
            f"no device named {name!r}; valid names: {', '.join(DEVICE_NAMES)}"
        )
    return found.tag


def name_of(tag: int | str) -> str:
    """The device name of a tag, or of a name (checked)."""
    if isinstance(tag, str):
        tag_of(tag)
        return tag
    return spec_of_tag(tag).name
