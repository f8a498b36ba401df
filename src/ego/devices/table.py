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

Beside the devices, the table holds one :class:`FamilySpec` a family: the class that
serves it (``robot.<name>``, made by ``ego.Robot`` from here), where Webots lists it, the
wire command that reads it, and how a telemetry sample, the dashboard and a recording's
plot show it (:class:`Series`). Every consumer derives from the table: a family's
``names`` (:class:`ego.devices.base.Device`), the sample's keys (ego.core.telemetry), the
families the dashboard may switch and plots (served to the page), the recording's schema
and plots. Adding a sensor is a row here, its family's module and the emulator's model.
A :class:`DeviceTable` is a value: :meth:`DeviceTable.extended` gives a copy with more
rows (tests hand it to the consumers, which take a ``table``).
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass
from typing import Any

from ego.errors import UnknownDeviceError
from ego.seam.profile import Command, Firmware

__all__ = [
    "BATTERY",
    "CAMERA",
    "DEVICES",
    "FAMILIES",
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
_RAW = "raw counts"

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
        (f"ps{i}", "proximity", i, "DistanceSensor", _RAW, _ALL if i < 8 else _GCTRONIC)
        for i in range(10)
    ),
    # The ground module: Webots' firmware reads it with M; the stock firmware in Overo mode
    # answers M with nothing and leaves it to the Overo, which reads it over its own I2C
    # bus (/dev/i2c-3, ego.i2c; docs/protocol.md, "The Overo's own I2C bus").
    *((f"gs{i}", "floor", i, "DistanceSensor", _RAW, _ALL) for i in range(3)),
    *((f"ls{i}", "light", i, "LightSensor", _RAW, _ALL) for i in range(8)),
    ("accelerometer", "accelerometer", 0, "Accelerometer", "m/s²", _ALL),
    ("left wheel motor", "motors", 0, "Motor", "rad/s", _ALL),
    ("right wheel motor", "motors", 1, "Motor", "rad/s", _ALL),
    ("left wheel sensor", "encoders", 0, "PositionSensor", "rad", _ALL),
    ("right wheel sensor", "encoders", 1, "PositionSensor", "rad", _ALL),
    # In Overo mode L 8 and L 9 (body, front) are ignored. On the e-puck2 led1, led3,
    # led5, led7 are RGB (Webots' e-puck2: LED.set(0xRRGGBB); Profile.rgb_leds).
    *((f"led{i}", "leds", i, "LED", "on/off", _ALL if i < 8 else _WEBOTS | _EPUCK2)
      for i in range(10)),
    *((f"mic{i}", "microphones", i, "Microphone", _RAW, _ALL) for i in range(3)),
    # The Overo's own camera (V4L2), whichever firmware the dsPIC runs.
    ("camera", CAMERA, 0, "Camera", "pixels", _BOTH),
    # The e-puck2's (issue 25), appended so the e-puck1's tags stay.
    # Webots' E-puck.proto (version "2"): a DistanceSensor "tof" whose lookup table maps
    # 0..2 m to 19.8..2000 (ego.devices.tof), the "gyro" (raw counts, its LUT is 1:1).
    ("tof", "tof", 0, "DistanceSensor", "mm", _EPUCK2),
    ("gyro", "gyro", 0, "Gyro", _RAW, _EPUCK2),
    # The fourth microphone (front; mic0..mic3 are right, left, back, front on it).
    ("mic3", "microphones", 3, "Microphone", _RAW, _EPUCK2),
    ("speaker", "sound", 0, "Speaker", "sound", _EPUCK2),
)
#: The devices Webots has no device for (no tag): read through their family only.
_UNTAGGED: tuple[_Row, ...] = (
    ("magnetometer", "magnetometer", 0, "Magnetometer", "µT", _EPUCK2),
    ("temperature", "temperature", 0, "TemperatureSensor", "°C", _EPUCK2),
    ("button", "button", 0, "Button", "pressed", _EPUCK2),
    ("selector", "selector", 0, "Selector", "position", _EPUCK2),
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
    """One family of :class:`ego.Robot`, as the table knows it."""

    #: The attribute of ``ego.Robot`` (``robot.proximity``), its rows' ``family`` and its
    #: key in a telemetry sample.
    name: str
    #: The class that serves it, ``module:Class`` (ego.devices.families imports it).
    cls: str
    #: Its place in Webots' list of the robot's devices (``getDeviceByIndex``).
    webots_rank: int
    #: The wire command whose reply is its reading (None: not read, an actuator).
    command: Command | None = None
    #: How a sample shows it; None: not among a sample's readings (the motors, LEDs and
    #: battery have keys of their own).
    series: Series | None = None


_STEP_RAD = 2 * math.pi / 1000  # 1000 steps a wheel turn (ego.serial.profiles.STEPS_PER_TURN)
_SIDES = ("left", "right")

#: The families, in the order a sample, the dashboard and the plots list them.
_FAMILY_ROWS: tuple[FamilySpec, ...] = (
    FamilySpec("proximity", "ego.devices.proximity:ProximitySensors", 4, Command.PROXIMITY,
               Series("proximity", _RAW, (*(f"ps{i}" for i in range(8)), "IR8", "IR9"))),
    FamilySpec("light", "ego.devices.light:LightSensors", 6, Command.LIGHT,
               Series("light", f"{_RAW}, lower is brighter", tuple(f"ls{i}" for i in range(8)))),
    FamilySpec("floor", "ego.devices.floor:FloorSensors", 5, Command.FLOOR,
               Series("floor", _RAW, ("gs0", "gs1", "gs2"))),
    FamilySpec("accelerometer", "ego.devices.accelerometer:Accelerometer", 3,
               Command.ACCELEROMETER_RAW, Series("accelerometer", "m/s²", ("x", "y", "z"))),
    FamilySpec("encoders", "ego.devices.encoders:Encoders", 2, Command.GET_STEPS,
               Series("encoders", "steps", _SIDES, ("rad", _STEP_RAD))),
    FamilySpec("microphones", "ego.devices.microphones:Microphones", 7, Command.MIC_AMPLITUDE,
               Series("microphones", "amplitude, ADC counts", ("mic0", "mic1", "mic2", "mic3"))),
    FamilySpec("motors", "ego.devices.motors:Motors", 0),
    FamilySpec("leds", "ego.devices.leds:Leds", 1),
    FamilySpec("battery", "ego.devices.battery:Battery", 8, Command.BATTERY),
    # The e-puck2's (issue 25):
    FamilySpec("tof", "ego.devices.tof:TofSensor", 9, Command.TOF,
               Series("ToF distance", "mm", ("tof",))),
    FamilySpec("gyro", "ego.devices.gyro:Gyro", 10, Command.GYRO_RAW,
               Series("gyro", "deg/s", ("x", "y", "z"), (_RAW, 131.072))),
    FamilySpec("magnetometer", "ego.devices.magnetometer:Magnetometer", 11, Command.ALL_SENSORS,
               Series("magnetometer", "µT", ("x", "y", "z"))),
    FamilySpec("temperature", "ego.devices.temperature:Temperature", 12, Command.ALL_SENSORS,
               Series("temperature", "°C", ("temperature",))),
    FamilySpec("button", "ego.devices.button:Button", 13, Command.BUTTON,
               Series("button", "pressed", ("button",))),
    FamilySpec("selector", "ego.devices.selector:Selector", 14, Command.ALL_SENSORS,
               Series("selector", "position", ("selector",))),
    FamilySpec("sound", "ego.devices.sound:Speaker", 15),
)  # fmt: skip


class DeviceTable:
    """The devices and families of a robot: rows looked up by name, tag and family."""

    def __init__(
        self,
        rows: Iterable[_Row],
        battery: DeviceSpec,
        families: Iterable[FamilySpec],
        untagged: Iterable[_Row] = (),
    ) -> None:
        #: Every device with a tag, in tag order (``devices[tag - 1].tag == tag``).
        self.devices: tuple[DeviceSpec, ...] = tuple(
            DeviceSpec(name, tag, family, index, kind, units, firmwares)
            for tag, (name, family, index, kind, units, firmwares) in enumerate(rows, start=1)
        )
        #: The battery: a raw count or a low flag (``robot.battery``); no Webots device.
        self.battery = battery
        #: The families of ``ego.Robot``, in the order a sample lists them.
        self.families: tuple[FamilySpec, ...] = tuple(families)
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


#: The e-puck's table.
TABLE = DeviceTable(
    _ROWS,
    DeviceSpec("battery", None, "battery", 0, "BatterySensor", _RAW, _GCTRONIC | _EPUCK2),
    _FAMILY_ROWS,
    _UNTAGGED,
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
