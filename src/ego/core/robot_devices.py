"""A Robot's device families: made from the device table for the channel's profile, found
by name, and reached as typed attributes (``robot.proximity``)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Generic, Protocol, TypeVar, overload

from ego.devices.base import Device, Sensor
from ego.devices.families import make_families
from ego.devices.leds import Leds
from ego.devices.motors import Motors
from ego.devices.table import CAMERA, TABLE, DeviceTable
from ego.errors import UnknownDeviceError

if TYPE_CHECKING:
    from ego.i2c.side import OveroI2C
    from ego.seam.profile import Profile

__all__ = ["FamilyAttribute", "HasDevices", "RobotDevices"]

_D = TypeVar("_D", bound=Device)


class RobotDevices:
    """One object per family of ``table``, for ``profile``, its sensors bound to the I2C bus."""

    def __init__(self, profile: Profile, i2c: OveroI2C, table: DeviceTable = TABLE) -> None:
        self._table = table
        # One of each family the device table names (ego.devices.table), by its name.
        self.by_name: dict[str, Device] = make_families(profile, table)
        #: The device families, in the order Webots names their devices.
        self.families: tuple[Device, ...] = tuple(self.by_name.values())
        #: What each step's transaction runs over (ego.core.transaction).
        self.step_parts: tuple[Device, ...] = tuple(
            part for family in self.families for part in family.parts
        )
        for part in self.step_parts:
            if isinstance(part, Sensor):
                part.bind_i2c(i2c)

    def get(self, name: str, cls: type[_D]) -> _D:
        """The family ``name``, checked to be a ``cls`` (for a typed attribute)."""
        found = self.by_name.get(name)
        if not isinstance(found, cls):
            raise UnknownDeviceError(f"the device table's family {name!r} is not a {cls.__name__}")
        return found

    def family(self, name: str) -> Device:
        """The family the device table calls ``name``; UnknownDeviceError listing them else."""
        found = self.by_name.get(name)
        if found is None:
            raise UnknownDeviceError(
                f"no device family {name!r}; valid families: {', '.join(self.by_name)}"
            )
        return found

    def device(self, name: str) -> Device:
        """The family serving the Webots device ``name`` ("ps3", "left wheel motor"...).

        The device table says which family; the family says whether the connected
        firmware has it (ps8, ps9: the Overo's only).
        """
        found = self._table.find(name)
        if found is not None and found.webots_device and found.family != CAMERA:
            family = self.by_name.get(found.family)
            if family is not None and name in family.member_names:
                return family
        raise UnknownDeviceError(
            f"no device named {name!r}; valid names: {', '.join(self.device_names)}"
        )

    @property
    def device_names(self) -> tuple[str, ...]:
        """Every Webots device name this robot answers to, by family, camera last."""
        rank = {id(family): i for i, family in enumerate(self.families)}
        devices = self._table.devices
        served = sorted(
            (rank[id(family)], s.index, s.name)
            for s in devices
            if (family := self.by_name.get(s.family)) is not None
            and s.name in family.member_names
        )
        return (*(name for _, _, name in served), *(s.name for s in devices if s.family == CAMERA))

    def heard_ascii(self, letter: str, profile: Profile) -> None:
        """The dsPIC ran the ASCII command ``letter``: after a stop, ego's view follows.

        ``S`` (stop) differs between the firmwares (docs/protocol.md, quirk "S"): the
        stock one stops the wheels and the ring LEDs but keeps echoing the old speeds in
        ``E``; Webots' also clears that echo and the body and front LEDs. On the stock
        firmware a ``D 0 0`` goes with the next batch so that ``E`` echoes the truth:
        otherwise ego's speed check would see a mismatch and send the old speeds again.
        """
        if letter.upper() == "S":
            stop = profile.ascii_stop
            self.get("motors", Motors).stopped_by_firmware(resend=not stop.clears_echo)
            self.get("leds", Leds).switched_off(stop.leds)

    def restarted(self, profile: Profile) -> None:
        """The dsPIC restarted (its firmware re-detected): every part re-sends what it lost."""
        for family in self.families:
            family.set_profile(profile)
            for part in family.parts:
                part.reset()


class HasDevices(Protocol):
    """What holds a :class:`RobotDevices` as ``devices`` (the Robot)."""

    @property
    def devices(self) -> RobotDevices: ...


class FamilyAttribute(Generic[_D]):
    """A typed attribute of the Robot for the family class ``cls``: its name is the one
    the class declares (``@family("proximity", ...)``), never restated."""

    def __init__(self, cls: type[_D]) -> None:
        self._cls = cls
        self._name = cls.table_family

    def __set_name__(self, owner: type, name: str) -> None:
        if name != self._name:
            raise TypeError(
                f"{owner.__name__}.{name} holds the family {self._name!r}: name it so"
            )

    @overload
    def __get__(self, robot: None, owner: type) -> FamilyAttribute[_D]: ...
    @overload
    def __get__(self, robot: HasDevices, owner: type) -> _D: ...
    def __get__(self, robot: HasDevices | None, owner: type) -> FamilyAttribute[_D] | _D:
        if robot is None:
            return self
        return robot.devices.get(self._name, self._cls)
