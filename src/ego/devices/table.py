"""The e-puck's devices, one row each: the table every face and ``Robot.device`` derive from.

A row (:class:`DeviceSpec`) says what the device is called in Webots, the integer tag
``wb_robot_get_device`` returns for it (its place in :data:`DEVICES`, from 1: public,
never renumbered), which family of :class:`ego.Robot` serves it (the attribute:
``robot.proximity``...) and at which index, its Webots node type, the units the Webots
face reports it in, and the firmwares that serve it.

``firmwares`` holds the names of :class:`ego.seam.profile.Firmware` whose profile (as
``PROFILES`` gives it, the stock firmware in Overo mode for ``gctronic``) serves the
device, over the line or, for what that firmware leaves on the Overo's own I2C bus
(``Profile.i2c``: gs0..gs2, a rev 1.3's accelerometer), over that bus: the families
refuse it on the others (``UnsupportedDeviceError``), or, for ps8 and ps9, do not have
it. A device needs its hardware too: gs0..gs2 the ground module, read on the Overo only
where its I2C bus is reachable (ego runs on the robot). The stock firmware in another
selector (over Bluetooth) also serves led8, led9.

The battery has a row but no tag: Webots reads it through the robot
(``batterySensorGetValue``), not as a device.

Beside the devices, the table holds one :class:`FamilySpec` a family, which the family's
class declares, once, where it is written (:meth:`DeviceTable.declare`)::

    @TABLE.declare("tof", webots_rank=9, series=Series("ToF distance", "mm", ("tof",)))
    class TofSensor(ArraySensor): ...

The declaration says which rows the class serves (``robot.tof``: its ``names`` are the
rows', never written in the class), where Webots lists it, and how a telemetry sample,
the dashboard and a recording's plot show it (:class:`Series`). Every consumer derives
from it: the Robot's families and typed attributes, the sample's keys
(ego.core.telemetry), the families the dashboard may switch and plots, the recording's
schema. ``ego.devices`` imports every family module, so that importing any of ego's
devices declares them all, in the order a sample lists them. Adding a sensor is a row
here, its family's module and the emulator's model. :meth:`DeviceTable.extended` gives a
copy with more rows (tests declare a family against it and hand it to the consumers,
which take a ``table``).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from typing import Any, TypeVar

from ego.errors import UnknownDeviceError
from ego.seam.profile import Firmware

__all__ = [
    "BATTERY",
    "CAMERA",
    "DEVICES",
    "FAMILIES",
    "RAW",
    "STEP_RAD",
    "TABLE",
    "DeviceSpec",
    "DeviceTable",
    "FamilySpec",
    "Series",
    "find",
    "names_of",
    "spec",
    "spec_of_tag",
]

_BOTH = frozenset({Firmware.GCTRONIC.value, Firmware.WEBOTS.value})
_GCTRONIC = frozenset({Firmware.GCTRONIC.value})
_WEBOTS = frozenset({Firmware.WEBOTS.value})
#: The e-puck2's asercom v2 (USB, Bluetooth) serves the e-puck1's sensors and its own.
_EPUCK2 = frozenset({Firmware.EPUCK2.value})
_ALL = _BOTH | _EPUCK2
#: Through a Pi-puck (ego.backends.pipuck): the e-puck2's I2C packet, York's e-puck1 map;
#: what both serve beside the microcontroller (IMU, ToF, ground module, camera, battery).
_I2C2 = frozenset({Firmware.EPUCK2_I2C.value})
_YORK = frozenset({Firmware.YORK.value})
_PIPUCK = _I2C2 | _YORK
#: The unit of a raw ADC or sensor count.
RAW = "raw counts"
_RAW = RAW

#: The family of the camera, which is no dsPIC family (``robot.camera``).
CAMERA = "camera"


@dataclass(frozen=True, slots=True)
class DeviceSpec:
    """One device of the e-puck, as the table knows it."""

    #: Webots' name: "ps0", "left wheel motor", "camera".
    name: str
    #: What ``wb_robot_get_device`` returns (1..); None for a device Webots does not name.
    tag: int | None
    #: The attribute of :class:`ego.Robot` holding the family that serves it ("proximity").
    family: str
    #: Its place among the family's members (ps3: 3, "right wheel motor": 1).
    index: int
    #: The Webots node type: "DistanceSensor", "LightSensor", "Motor", "PositionSensor"...
    kind: str
    #: The units the Webots face reports it in ("raw counts", "rad/s", "rad", "m/s²").
    units: str
    #: The names of the firmwares that serve it (``Firmware.value``).
    firmwares: frozenset[str]

    @property
    def webots_device(self) -> bool:
        """Whether Webots knows it as a device (``getDevice``); the battery it does not."""
        return self.tag is not None

    def served_by(self, firmware: Firmware | str) -> bool:
        """Whether ``firmware`` (a :class:`Firmware` or its name) serves this device."""
        return Firmware(firmware).value in self.firmwares


_Row = tuple[str, str, int, str, str, frozenset[str]]

#: In tag order: a row's tag is its place here, from 1. Append only.
_ROWS: tuple[_Row, ...] = (
    # ps8 and ps9 are the Overo board's long-range IR8 and IR9 (docs/protocol.md).
    *(
        (f"ps{i}", "proximity", i, "DistanceSensor", _RAW, _ALL | _PIPUCK if i < 8 else _GCTRONIC)
        for i in range(10)
    ),
    # The ground module: Webots' firmware reads it with M; the stock firmware in Overo mode
    # answers M with nothing and leaves it to the Overo, which reads it over its own I2C
    # bus (/dev/i2c-3, ego.i2c; docs/protocol.md, "The Overo's own I2C bus").
    *((f"gs{i}", "floor", i, "DistanceSensor", _RAW, _ALL | _PIPUCK) for i in range(3)),
    *((f"ls{i}", "light", i, "LightSensor", _RAW, _ALL | _PIPUCK) for i in range(8)),
    ("accelerometer", "accelerometer", 0, "Accelerometer", "m/s²", _ALL | _PIPUCK),
    ("left wheel motor", "motors", 0, "Motor", "rad/s", _ALL | _PIPUCK),
    ("right wheel motor", "motors", 1, "Motor", "rad/s", _ALL | _PIPUCK),
    ("left wheel sensor", "encoders", 0, "PositionSensor", "rad", _ALL | _PIPUCK),
    ("right wheel sensor", "encoders", 1, "PositionSensor", "rad", _ALL | _PIPUCK),
    # In Overo mode L 8 and L 9 (body, front) are ignored. On the e-puck2 led1, led3,
    # led5, led7 are RGB (Webots' e-puck2: LED.set(0xRRGGBB); Profile.rgb_leds).
    # The e-puck2's I2C packet has no body or front LED; York's map has both.
    *((f"led{i}", "leds", i, "LED", "on/off",
       _ALL | _PIPUCK if i < 8 else _WEBOTS | _EPUCK2 | _YORK) for i in range(10)),
    *((f"mic{i}", "microphones", i, "Microphone", _RAW, _ALL | _I2C2) for i in range(3)),
    # The Overo's own camera (V4L2), whichever firmware the dsPIC runs.
    # The Pi-puck's: a USB video device behind its FT903.
    ("camera", CAMERA, 0, "Camera", "pixels", _BOTH | _PIPUCK),
    # The e-puck2's (issue 25), appended so the e-puck1's tags stay.
    # Webots' E-puck.proto (version "2"): a DistanceSensor "tof" whose lookup table maps
    # 0..2 m to 19.8..2000 (ego.devices.tof), the "gyro" (raw counts, its LUT is 1:1).
    ("tof", "tof", 0, "DistanceSensor", "mm", _EPUCK2 | _PIPUCK),
    ("gyro", "gyro", 0, "Gyro", _RAW, _EPUCK2 | _PIPUCK),
    # The fourth microphone (front; mic0..mic3 are right, left, back, front on it).
    ("mic3", "microphones", 3, "Microphone", _RAW, _EPUCK2 | _I2C2),
    ("speaker", "sound", 0, "Speaker", "sound", _EPUCK2 | _I2C2),
)
#: The devices Webots has no device for (no tag): read through their family only.
_UNTAGGED: tuple[_Row, ...] = (
    ("magnetometer", "magnetometer", 0, "Magnetometer", "µT", _EPUCK2),
    ("temperature", "temperature", 0, "TemperatureSensor", "°C", _EPUCK2),
    ("button", "button", 0, "Button", "pressed", _EPUCK2 | _I2C2),
    ("selector", "selector", 0, "Selector", "position", _EPUCK2 | _I2C2),
)


@dataclass(frozen=True, slots=True)
class Series:
    """How a sample shows a family: the plots' title, unit and lines (the page's and
    ``ego plot``'s), and the unit a Webots user reads it in, if another (unit, factor)."""

    title: str
    unit: str
    #: Each line's name, by index in the family's values.
    lines: tuple[str, ...]
    webots: tuple[str, float] | None = None

    def describe(self, key: str) -> dict[str, Any]:
        """As the dashboard's page is told it (JSON)."""
        found: dict[str, Any] = {"key": key, "title": self.title, "unit": self.unit,
                                 "lines": list(self.lines)}  # fmt: skip
        if self.webots is not None:
            found["webots"] = {"unit": self.webots[0], "per": self.webots[1]}
        return found


@dataclass(frozen=True, slots=True)
class FamilySpec:
    """One family of :class:`ego.Robot`, as its class declares it (:meth:`DeviceTable.declare`)."""

    #: The attribute of ``ego.Robot`` (``robot.proximity``), its rows' ``family`` and its
    #: key in a telemetry sample.
    name: str
    #: The class that serves it (an :class:`ego.devices.base.Device`).
    cls: type
    #: Its place in Webots' list of the robot's devices (``getDeviceByIndex``).
    webots_rank: int
    #: How a sample shows it; None: not among a sample's readings (the motors, LEDs and
    #: battery have keys of their own).
    series: Series | None = None


#: One wheel step in rad: 1000 steps a wheel turn (ego.serial.profiles.STEPS_PER_TURN).
STEP_RAD = 2 * math.pi / 1000
_C = TypeVar("_C", bound=type)

class DeviceTable:
    """The devices and families of a robot: rows looked up by name, tag and family."""

    def __init__(
        self,
        rows: Iterable[_Row],
        battery: DeviceSpec,
        families: Iterable[FamilySpec] = (),
        untagged: Iterable[_Row] = (),
    ) -> None:
        #: Every device with a tag, in tag order (``devices[tag - 1].tag == tag``).
        self.devices: tuple[DeviceSpec, ...] = tuple(
            DeviceSpec(name, tag, family, index, kind, units, firmwares)
            for tag, (name, family, index, kind, units, firmwares) in enumerate(rows, start=1)
        )
        #: The battery: a raw count or a low flag (``robot.battery``); no Webots device.
        self.battery = battery
        self._families: list[FamilySpec] = list(families)
        untagged = tuple(untagged)
        #: The devices Webots has no device for (no tag), the battery aside.
        self.untagged: tuple[DeviceSpec, ...] = tuple(
            DeviceSpec(name, None, family, index, kind, units, firmwares)
            for name, family, index, kind, units, firmwares in untagged
        )
        self.by_name: dict[str, DeviceSpec] = {
            s.name: s for s in (*self.devices, battery, *self.untagged)
        }
        self._rows = tuple(rows)
        self._untagged = tuple(untagged)

    def extended(
        self, rows: Iterable[_Row] = (), families: Iterable[FamilySpec] = ()
    ) -> DeviceTable:
        """A copy of this table with ``rows`` appended (their tags follow) and ``families``."""
        return DeviceTable(
            (*self._rows, *rows), self.battery, (*self.families, *families), self._untagged
        )

    @property
    def families(self) -> tuple[FamilySpec, ...]:
        """The families of ``ego.Robot``, in the order a sample lists them (declared)."""
        return tuple(self._families)

    def declare(
        self, name: str, *, webots_rank: int, series: Series | None = None
    ) -> Callable[[_C], _C]:
        """Declare the decorated class as the family ``name`` of this table: the one
        declaration of a family. The class takes the rows' names (``names``) and its
        ``table_family``; the table lists it (``families``) for every consumer."""

        def declared(cls: _C) -> _C:
            if any(f.name == name for f in self._families):
                raise ValueError(f"the device family {name!r} is declared twice")
            self.part_of(name)(cls)
            self._families.append(FamilySpec(name, cls, webots_rank, series))
            return cls

        return declared

    def part_of(self, name: str) -> Callable[[_C], _C]:
        """Make the decorated class a part of the family ``name`` (the motors' speeds and
        their read-back...): it takes the family's names, and is no family itself."""
        names = self.names_of(name)

        def part(cls: _C) -> _C:
            setattr(cls, "table_family", name)  # noqa: B010 (any class: typed as _C)
            setattr(cls, "names", names)  # noqa: B010
            return cls

        return part

    @property
    def family_names(self) -> tuple[str, ...]:
        """The families in the table, in order of their first device (camera included)."""
        return tuple(dict.fromkeys(s.family for s in self.by_name.values()))

    def find(self, name: object) -> DeviceSpec | None:
        """The row of the device called ``name``, or None."""
        return self.by_name.get(name) if isinstance(name, str) else None

    def spec(self, name: str) -> DeviceSpec:
        """The row of the device called ``name``; UnknownDeviceError listing the names else."""
        found = self.find(name)
        if found is None:
            raise UnknownDeviceError(
                f"no device named {name!r}; valid names: {', '.join(self.by_name)}"
            )
        return found

    def spec_of_tag(self, tag: int) -> DeviceSpec:
        """The row of the device ``tag`` (as ``wb_robot_get_device`` returns it)."""
        count = len(self.devices)
        if isinstance(tag, bool) or not isinstance(tag, int) or not 1 <= tag <= count:
            raise UnknownDeviceError(
                f"device tag {tag!r} is not one of 1..{count} "
                "(the tags wb_robot_get_device returns)"
            )
        return self.devices[tag - 1]

    def names_of(self, family: str) -> tuple[str, ...]:
        """The device names the family ``family`` (a Robot attribute) serves, by index."""
        rows = sorted(self.by_name.values(), key=lambda s: s.index)
        names = tuple(s.name for s in rows if s.family == family)
        if not names:
            raise UnknownDeviceError(
                f"no device family {family!r}; valid families: {', '.join(self.family_names)}"
            )
        return names

    def family(self, name: str) -> FamilySpec:
        """The family ``name`` (a Robot attribute); UnknownDeviceError listing them else."""
        for found in self.families:
            if found.name == name:
                return found
        raise UnknownDeviceError(
            f"no device family {name!r}; valid families: "
            f"{', '.join(f.name for f in self.families)}"
        )

    @property
    def sampled(self) -> tuple[FamilySpec, ...]:
        """The families a telemetry sample holds readings of, in its order."""
        return tuple(f for f in self.families if f.series is not None)

    @property
    def switchable(self) -> tuple[str, ...]:
        """What the dashboard's page may switch on and off: the sampled families, camera."""
        return (*(f.name for f in self.sampled), CAMERA)

    def describe_series(self) -> list[dict[str, Any]]:
        """The sampled families as the dashboard's page draws them (JSON)."""
        return [f.series.describe(f.name) for f in self.sampled if f.series is not None]


#: The e-puck's table (its families are declared by their classes: ego.devices).
TABLE = DeviceTable(
    _ROWS,
    DeviceSpec("battery", None, "battery", 0, "BatterySensor", _RAW,
               _GCTRONIC | _EPUCK2 | _PIPUCK),
    untagged=_UNTAGGED,
)
#: Every device with a tag, in tag order (``DEVICES[tag - 1].tag == tag``).
DEVICES: tuple[DeviceSpec, ...] = TABLE.devices
#: The battery: a raw count or a low flag (``robot.battery``); Webots has no device for it.
BATTERY = TABLE.battery

_BY_NAME: dict[str, DeviceSpec] = TABLE.by_name
#: The families in the table, in order of their first device.
FAMILIES: tuple[str, ...] = TABLE.family_names


def find(name: object) -> DeviceSpec | None:
    """The row of the device called ``name``, or None."""
    return TABLE.find(name)


def spec(name: str) -> DeviceSpec:
    """The row of the device called ``name``; UnknownDeviceError listing the names else."""
    return TABLE.spec(name)


def spec_of_tag(tag: int) -> DeviceSpec:
    """The row of the device ``tag`` (as ``wb_robot_get_device`` returns it)."""
    return TABLE.spec_of_tag(tag)


def names_of(family: str) -> tuple[str, ...]:
    """The device names the family ``family`` (a Robot attribute) serves, in index order."""
    return TABLE.names_of(family)
