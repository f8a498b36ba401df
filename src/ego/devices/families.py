"""A robot's device families, made from the device table: one of each, in Webots' order."""

from __future__ import annotations

from typing import TypeVar

from ego.devices.base import Device
from ego.devices.table import TABLE, DeviceTable, FamilySpec
from ego.errors import UnknownDeviceError
from ego.seam.profile import Profile

__all__ = ["family_class", "make_families", "pick"]

_D = TypeVar("_D", bound=Device)


def family_class(spec: FamilySpec) -> type[Device]:
    """The class that declared the family ``spec``, checked to be a device family of it."""
    found = spec.cls
    if not (isinstance(found, type) and issubclass(found, Device)):
        raise UnknownDeviceError(f"the device table's family {spec.name!r} is served by "
                                 f"{found!r}, which is no device family class")  # fmt: skip
    if found.table_family != spec.name:
        raise UnknownDeviceError(f"{found.__name__} serves the table's family "
                                 f"{found.table_family!r}, not {spec.name!r}")  # fmt: skip
    return found


def make_families(profile: Profile, table: DeviceTable = TABLE) -> dict[str, Device]:
    """One of each family of ``table`` for a robot on ``profile``, by name, in the order
    Webots lists the robot's devices."""
    ranked = sorted(table.families, key=lambda f: f.webots_rank)
    return {spec.name: family_class(spec)(profile) for spec in ranked}


def pick(families: dict[str, Device], name: str, cls: type[_D]) -> _D:
    """The family ``name`` of ``families``, checked to be a ``cls`` (for a typed attribute)."""
    found = families.get(name)
    if not isinstance(found, cls):
        raise UnknownDeviceError(f"the device table's family {name!r} is not a {cls.__name__}")
    return found
