"""The device table (ego.devices.table) agrees with every family, every face and the tags.

The table is the one place a device's name, tag, family, kind and firmwares are written;
these tests hold it to what the families do on each emulated firmware, and show that the
faces find devices through it (each row's kind and family are what the faces use).
"""

from __future__ import annotations

from collections.abc import Iterator

import pytest

import ego
from ego import overo
from ego import webots as wb
from ego.controller import Robot as WebotsRobot
from ego.controller.device import view_class
from ego.devices import table
from ego.devices.table import BATTERY, CAMERA, DEVICES, FAMILIES, names_of, spec, spec_of_tag
from ego.errors import UnknownDeviceError, UnsupportedDeviceError
from ego.faces import tags
from ego.faces.default_robot import FaceContext, activate
from ego.faces.runtime import RunOptions
from ego.seam.profile import Firmware
from firmware_sim import Emulator

#: The tags as ego 0.1 published them: a device's tag is its place here, from 1.
PUBLISHED_NAMES = (
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
    # Appended for the e-puck2 (issue 25): the e-puck1's tags above never move.
    "tof",
    "gyro",
    "mic3",
    "speaker",
)
#: Webots' e-puck model: the node type of each family's devices (None: no Webots device).
E_PUCK_NODES = {
    "proximity": "DistanceSensor",
    "floor": "DistanceSensor",  # the ground sensors are distance sensors in Webots
    "light": "LightSensor",
    "accelerometer": "Accelerometer",
    "motors": "Motor",
    "encoders": "PositionSensor",
    "leds": "LED",
    "camera": "Camera",
    "microphones": None,
    "battery": None,
    # The e-puck2's (Webots' E-puck.proto, version "2"):
    "tof": "DistanceSensor",
    "gyro": "Gyro",
    "sound": "Speaker",
    "magnetometer": None,
    "temperature": None,
    "button": None,
    "selector": None,
}
#: The Webots node types that Webots' e-puck has a device class for.
WEBOTS_KINDS = {kind for kind in E_PUCK_NODES.values() if kind is not None}
NOT_CAMERA = [s for s in DEVICES if s.family != CAMERA]


@pytest.fixture(params=[Firmware.WEBOTS, Firmware.GCTRONIC], ids=str)
def firmware_emulator(request: pytest.FixtureRequest) -> Iterator[Emulator]:
    """Each firmware's dsPIC on a pty."""
    with Emulator(request.param.value, seed=1) as emu:
        yield emu


@pytest.fixture
def robot(firmware_emulator: Emulator) -> Iterator[ego.Robot]:
    """A core robot on each firmware, probed (so that the battery's revision is known),
    with the robot's own I2C bus where the firmware leaves devices on it (Overo mode)."""
    with ego.Robot(firmware_emulator.path, i2c=firmware_emulator.i2c) as opened:
        yield opened


# -- tags ----------------------------------------------------------------------------------


def test_the_tags_are_the_published_ones() -> None:
    assert tags.DEVICE_NAMES == PUBLISHED_NAMES
    for tag, name in enumerate(PUBLISHED_NAMES, start=1):
        assert tags.tag_of(name) == tag == spec(name).tag
        assert tags.name_of(tag) == name == spec_of_tag(tag).name
    assert [s.tag for s in DEVICES] == list(range(1, len(PUBLISHED_NAMES) + 1))


@pytest.mark.parametrize("tag", [0, -1, len(PUBLISHED_NAMES) + 1, True, 1.0, "1"])
def test_a_tag_outside_the_table_is_refused_naming_the_range(tag: object) -> None:
    with pytest.raises(UnknownDeviceError, match=rf"is not one of 1\.\.{len(PUBLISHED_NAMES)}"):
        spec_of_tag(tag)  # type: ignore[arg-type]


def test_an_unknown_name_is_refused_listing_the_names() -> None:
    with pytest.raises(UnknownDeviceError, match=r"'sonar'; valid names: ps0, ps1, .* battery"):
        spec("sonar")
    with pytest.raises(UnknownDeviceError, match=r"'battery'; valid names: ps0, .* camera, tof"):
        tags.tag_of("battery")  # a row without a tag: Webots has no such device


def test_names_of_gives_a_family_in_index_order() -> None:
    assert names_of("motors") == ("left wheel motor", "right wheel motor")
    assert names_of("proximity") == tuple(f"ps{i}" for i in range(10))
    assert names_of("battery") == ("battery",)
    with pytest.raises(UnknownDeviceError, match="valid families: proximity, floor"):
        names_of("sonar")
    untagged = {s.family for s in table.TABLE.untagged}  # the e-puck2's magnetometer...
    assert {s.family for s in DEVICES} | {"battery"} | untagged == set(FAMILIES)


# -- the families ----------------------------------------------------------------------------


def test_every_family_serves_exactly_its_rows(robot: ego.Robot) -> None:
    served = {name for family in robot.families for name in type(family).names}
    untagged = {s.name for s in table.TABLE.untagged}
    assert served == {s.name for s in NOT_CAMERA} | {"battery"} | untagged
    for family in robot.families:
        attribute = next(a for a in FAMILIES if getattr(robot, a, None) is family)
        assert type(family).names == names_of(attribute)
        assert family.webots_device is spec(type(family).names[0]).webots_device


def test_robot_device_serves_every_row_its_firmware_has(robot: ego.Robot) -> None:
    firmware = robot.channel.profile.firmware
    for row in NOT_CAMERA:
        family = getattr(robot, row.family)
        if row.name in family.member_names:
            assert robot.device(row.name) is family
            assert type(family).names[row.index] == row.name
        else:  # ps8, ps9: the Overo board's own sensors
            assert not row.served_by(firmware)
            with pytest.raises(UnknownDeviceError, match=repr(row.name)):
                robot.device(row.name)
    with pytest.raises(UnknownDeviceError):
        robot.device(BATTERY.name)  # Webots reads it through the robot
    names = robot.device_names
    assert names[-1] == "camera" and names[:2] == ("left wheel motor", "right wheel motor")
    assert set(names) == {s.name for s in DEVICES if s.name in names}


def _use(robot: ego.Robot, name: str) -> None:
    """What a controller does first with the device ``name``."""
    row = spec(name)
    if row.family == "leds":
        robot.leds.set(name, 1)
    elif row.family == "motors":
        robot.motors.set_speed(100, 100)
    elif row.family == "battery":
        robot.battery.enable(32)
    else:
        robot.device(name).enable(32, [name])  # type: ignore[attr-defined]


def test_the_firmwares_of_a_row_are_those_that_serve_it(robot: ego.Robot) -> None:
    firmware = robot.channel.profile.firmware
    for row in [*NOT_CAMERA, BATTERY]:
        if row.served_by(firmware):
            _use(robot, row.name)
        else:
            with pytest.raises((UnsupportedDeviceError, UnknownDeviceError)):
                _use(robot, row.name)
    for _ in range(3):
        assert robot.step(32) == 0  # everything served answers
    assert robot.floor.enabled is spec("gs0").served_by(firmware)
    assert robot.battery.has_values is BATTERY.served_by(firmware)


@pytest.mark.parametrize("row", [*DEVICES, BATTERY], ids=lambda s: s.name)
def test_a_rows_kind_is_webots_node_type_for_the_e_puck(row: table.DeviceSpec) -> None:
    expected = E_PUCK_NODES[row.family]
    if expected is None:
        assert row.kind not in WEBOTS_KINDS
    else:
        assert row.kind == expected and row.webots_device


def test_served_by_takes_the_enum_or_its_name() -> None:
    assert spec("led8").served_by(Firmware.WEBOTS) and spec("led8").served_by("webots")
    assert not spec("led8").served_by("gctronic")
    assert BATTERY.served_by("gctronic") and not BATTERY.served_by(Firmware.WEBOTS)


# -- the faces -------------------------------------------------------------------------------


@pytest.mark.parametrize("row", DEVICES, ids=lambda s: s.name)
def test_the_webots_view_class_is_the_rows_kind(row: table.DeviceSpec) -> None:
    cls = view_class(row.name)
    if row.kind in WEBOTS_KINDS:
        assert cls is not None and cls.__name__ == row.kind
    else:
        assert cls is None  # the microphones: Webots' e-puck has none
    assert view_class(BATTERY.name) is None and view_class("sonar") is None


def test_the_webots_faces_resolve_every_name_through_the_table(
    firmware_emulator: Emulator,
) -> None:
    options = RunOptions(port=firmware_emulator.path)
    controller = WebotsRobot(options=options)
    try:
        names = controller.core.device_names
        served = [s for s in DEVICES if s.kind in WEBOTS_KINDS and s.name in names]
        assert len(served) >= len(names) - 3  # all but the microphones
        for row in served:
            assert type(controller.getDevice(row.name)).__name__ == row.kind
    finally:
        controller.cleanup()
    with activate(FaceContext(options)):
        assert wb.wb_robot_init() == 1
        try:
            for row in served:
                assert wb.wb_robot_get_device(row.name) == row.tag
        finally:
            wb.wb_robot_cleanup()


def test_the_overo_face_resolves_every_tag_through_the_table() -> None:
    with activate(FaceContext(RunOptions(port="sim", seed=1))):
        overo.overo_serial_init()
        try:
            for row in DEVICES:
                for check, kind in (
                    (overo._distance_name, "DistanceSensor"),
                    (overo._light_name, "LightSensor"),
                ):
                    if row.kind == kind:
                        assert check(row.tag) == row.name  # type: ignore[arg-type]
                    else:
                        with pytest.raises(UnknownDeviceError, match=repr(row.name)):
                            check(row.tag)  # type: ignore[arg-type]
                if row.family == "microphones" and row.name != "mic3":  # the e-puck2's
                    overo.overo_microphone_enable(row.tag, 32)  # type: ignore[arg-type]
                else:
                    with pytest.raises(UnknownDeviceError, match="mic0, mic1, mic2"):
                        overo.overo_microphone_enable(row.tag, 32)  # type: ignore[arg-type]
        finally:
            overo.overo_serial_close()


@pytest.mark.parametrize("row", DEVICES, ids=lambda row: row.name)
def test_each_rows_kind_is_the_webots_class_the_face_gives(row: table.DeviceSpec) -> None:
    """The Webots face's class of a device is its row's kind, for every row (the face
    reads the table: no second list of kinds to keep in step)."""
    found = view_class(row.name)
    if not row.webots_device or row.kind not in WEBOTS_KINDS:  # the microphones
        assert found is None
    else:
        assert found is not None and found.__name__ == row.kind


def test_robot_device_finds_each_family_through_the_table(robot: ego.Robot) -> None:
    served = set(robot.device_names)
    for row in NOT_CAMERA:
        if row.webots_device and row.name in served:
            assert robot.device(row.name) is getattr(robot, row.family), row.name
        else:
            with pytest.raises(UnknownDeviceError, match=repr(row.name)):
                robot.device(row.name)
