"""The e-puck's devices, one row each: the table every face and ``Robot.device`` derive from.

A row (:class:`DeviceSpec`) says what the device is called in Webots, the integer tag
``wb_robot_get_device`` returns for it (its place in :data:`DEVICES`, from 1: public,
never renumbered), which family of :class:`ego.Robot` serves it (the attribute:
``robot.proximity``...) and at which index, its Webots node type, the units the Webots
face reports it in, and the firmwares that serve it.

``firmwares`` holds the names of :class:`ego.serial.protocol.Firmware` whose profile (as
``PROFILES`` gives it, the stock firmware in Overo mode for ``gctronic``) serves the
device, over the line or, for what that firmware leaves on the Overo's own I2C bus
(``Profile.i2c``: gs0..gs2, a rev 1.3's accelerometer), over that bus: the families
refuse it on the others (``UnsupportedDeviceError``), or, for ps8 and ps9, do not have
it. A device needs its hardware too: gs0..gs2 the ground module, read on the Overo only
where its I2C bus is reachable (ego runs on the robot). The stock firmware in another
selector (over Bluetooth) also serves led8, led9.

The battery has a row but no tag: Webots reads it through the robot
(``batterySensorGetValue``), not as a device.
"""

from __future__ import annotations

from dataclasses import dataclass

from ego.errors import UnknownDeviceError
from ego.serial.protocol import Firmware

__all__ = [
    "BATTERY",
    "CAMERA",
    "DEVICES",
    "FAMILIES",
    "DeviceSpec",
    "find",
    "names_of",
    "spec",
    "spec_of_tag",
]

_BOTH = frozenset({Firmware.GCTRONIC.value, Firmware.WEBOTS.value})
_GCTRONIC = frozenset({Firmware.GCTRONIC.value})
_WEBOTS = frozenset({Firmware.WEBOTS.value})
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
        (f"ps{i}", "proximity", i, "DistanceSensor", _RAW, _BOTH if i < 8 else _GCTRONIC)
        for i in range(10)
    ),
    # The ground module: Webots' firmware reads it with M; the stock firmware in Overo mode
    # answers M with nothing and leaves it to the Overo, which reads it over its own I2C
    # bus (/dev/i2c-3, ego.i2c; docs/protocol.md, "The Overo's own I2C bus").
    *((f"gs{i}", "floor", i, "DistanceSensor", _RAW, _BOTH) for i in range(3)),
    *((f"ls{i}", "light", i, "LightSensor", _RAW, _BOTH) for i in range(8)),
    ("accelerometer", "accelerometer", 0, "Accelerometer", "m/s²", _BOTH),
    ("left wheel motor", "motors", 0, "Motor", "rad/s", _BOTH),
    ("right wheel motor", "motors", 1, "Motor", "rad/s", _BOTH),
    ("left wheel sensor", "encoders", 0, "PositionSensor", "rad", _BOTH),
    ("right wheel sensor", "encoders", 1, "PositionSensor", "rad", _BOTH),
    # In Overo mode L 8 and L 9 (body, front) are ignored.
    *((f"led{i}", "leds", i, "LED", "on/off", _BOTH if i < 8 else _WEBOTS) for i in range(10)),
    *((f"mic{i}", "microphones", i, "Microphone", _RAW, _BOTH) for i in range(3)),
    # The Overo's own camera (V4L2), whichever firmware the dsPIC runs.
    ("camera", CAMERA, 0, "Camera", "pixels", _BOTH),
)

#: Every device with a tag, in tag order (``DEVICES[tag - 1].tag == tag``).
DEVICES: tuple[DeviceSpec, ...] = tuple(
    DeviceSpec(name, tag, family, index, kind, units, firmwares)
    for tag, (name, family, index, kind, units, firmwares) in enumerate(_ROWS, start=1)
)
#: The battery: a raw count or a low flag (``robot.battery``); Webots has no device for it.
BATTERY = DeviceSpec("battery", None, "battery", 0, "BatterySensor", _RAW, _GCTRONIC)

_BY_NAME: dict[str, DeviceSpec] = {s.name: s for s in (*DEVICES, BATTERY)}
#: The families in the table, in order of their first device.
FAMILIES: tuple[str, ...] = tuple(dict.fromkeys(s.family for s in _BY_NAME.values()))


def find(name: object) -> DeviceSpec | None:
    """The row of the device called ``name``, or None."""
    return _BY_NAME.get(name) if isinstance(name, str) else None


def spec(name: str) -> DeviceSpec:
    """The row of the device called ``name``; UnknownDeviceError listing the names else."""
    found = find(name)
    if found is None:
        raise UnknownDeviceError(f"no device named {name!r}; valid names: {', '.join(_BY_NAME)}")
    return found


def spec_of_tag(tag: int) -> DeviceSpec:
    """The row of the device ``tag`` (as ``wb_robot_get_device`` returns it)."""
    if isinstance(tag, bool) or not isinstance(tag, int) or not 1 <= tag <= len(DEVICES):
        raise UnknownDeviceError(
            f"device tag {tag!r} is not one of 1..{len(DEVICES)} "
            "(the tags wb_robot_get_device returns)"
        )
    return DEVICES[tag - 1]


def names_of(family: str) -> tuple[str, ...]:
    """The device names the family ``family`` (a Robot attribute) serves, in index order."""
    names = tuple(
        s.name for s in sorted(_BY_NAME.values(), key=lambda s: s.index) if s.family == family
    )
    if not names:
        raise UnknownDeviceError(
            f"no device family {family!r}; valid families: {', '.join(FAMILIES)}"
        )
    return names
