"""Which firmware answers: the V and C replies into a profile (protocol.md, "Firmware profile")."""

from __future__ import annotations

import pytest

from ego.errors import DeprecatedNameWarning, ProtocolError, UnsupportedDeviceError
from ego.serial.firmware import (
    OVERO_SELECTOR,
    identify,
    is_gctronic,
    line_payload,
    parse_selector,
)
from ego.serial.protocol import Command, Firmware, Request, encode_batch
from firmware_sim.dspic import firmware_name

# protocol.md: "v,Version 1.2.2 August 2008 GCtronic / HW version: ...", or
# "v,Version 1.5.3 November 2016 (Webots)".
GCTRONIC = ["v,Version 1.2.2 August 2008 GCtronic", "HW version: 1.1"]
WEBOTS = ["v,Version 1.5.3 November 2016 (Webots)"]


def test_webots_firmware_gets_the_thesis_profile() -> None:
    """protocol.md: "The Webots firmware ... get[s] the thesis profile"."""
    info = identify(WEBOTS)
    assert info.firmware is Firmware.WEBOTS
    assert info.version == "Version 1.5.3 November 2016 (Webots)"
    assert info.detected


def test_gctronic_firmware_on_selector_10_gets_the_overo_profile() -> None:
    """protocol.md: "the ASCII C command (reply c,N) tells the selector position: 10 is the
    Overo mode"."""
    info = identify(GCTRONIC, selector=10)
    assert info.firmware is Firmware.GCTRONIC
    assert info.selector == OVERO_SELECTOR == 10
    assert info.hardware == "HW version: 1.1"
    assert info.profile.supports(Command.ACCELEROMETER_RAW)


@pytest.mark.parametrize("selector", [3, 0, 15, None])
def test_gctronic_firmware_on_another_selector_gets_the_thesis_profile(
    selector: int | None,
) -> None:
    info = identify(GCTRONIC, selector=selector)
    assert info.firmware is Firmware.WEBOTS
    assert info.selector == selector


def test_silence_gets_the_thesis_profile() -> None:
    """protocol.md: "a firmware that answers neither, get[s] the thesis profile"."""
    info = identify([])
    assert info.firmware is Firmware.WEBOTS
    assert info.version == ""


@pytest.mark.parametrize("hardware", ["HW version: 1.3", "HW version 1.3 (2014)"])
def test_hardware_1_3_on_overo_refuses_the_accelerometer(hardware: str) -> None:
    """protocol.md: "on hardware revision 1.3 a/A return zeros (that accelerometer is on I2C
    too)", and a device the firmware cannot serve "never reads zeros"."""
    info = identify([GCTRONIC[0], hardware], selector=10)
    assert info.firmware is Firmware.GCTRONIC
    for letter in "aA":
        with pytest.raises(UnsupportedDeviceError, match=r"1\.3"):
            encode_batch([Request(Command((-ord(letter)) & 0xFF))], info.profile)
    assert encode_batch([Request(Command.PROXIMITY)], info.profile).reply_size == 20


@pytest.mark.parametrize("hardware", ["HW version: 1.1", "HW version: 11.3", "HW version: 1.30"])
def test_other_hardware_keeps_the_accelerometer(hardware: str) -> None:
    info = identify([GCTRONIC[0], hardware], selector=10)
    assert info.profile.supports(Command.ACCELEROMETER_RAW)


def test_hardware_1_3_on_webots_firmware_keeps_the_accelerometer() -> None:
    info = identify([WEBOTS[0], "HW version: 1.3"])
    assert info.profile.supports(Command.ACCELEROMETER_RAW)


def test_version_line_from_another_command_is_refused() -> None:
    with pytest.raises(ProtocolError, match="does not start with 'v,'"):
        identify(["z,Command not found"])


@pytest.mark.parametrize(("line", "selector"), [("c,10\r\n", 10), ("c,3", 3), ("c,0", 0)])
def test_selector_reply_is_parsed(line: str, selector: int) -> None:
    assert parse_selector(line) == selector


@pytest.mark.parametrize("line", ["c,16", "c,-1", "c,ten", "c,", "s", "v,10"])
def test_malformed_selector_reply_is_refused(line: str) -> None:
    with pytest.raises(ProtocolError):
        parse_selector(line)


def test_line_payload_strips_the_letter_and_the_line_end() -> None:
    assert line_payload("v,Version 1.2.2\r\n", "V") == "Version 1.2.2"


@pytest.mark.parametrize(
    ("version", "gctronic"),
    [
        ("Version 1.2.2 August 2008 GCtronic", True),
        ("Version 1.5.3 November 2016 (Webots)", False),
        ("Version 2 GCtronic for Webots", False),
        ("", False),
    ],
)
def test_gctronic_is_recognised_by_its_version_text(version: str, gctronic: bool) -> None:
    assert is_gctronic(version) is gctronic


@pytest.mark.parametrize(("old", "new"), [("thesis", "webots"), ("gctronic-overo", "gctronic")])
def test_old_profile_names_still_work_and_warn(old: str, new: str) -> None:
    """The fidelity audit renamed the profiles after the firmwares they model."""
    with pytest.warns(DeprecatedNameWarning, match=f"{old!r} is deprecated: it is {new!r}"):
        assert Firmware.choose(old) is Firmware(new)


@pytest.mark.parametrize(("old", "new"), [("thesis", "webots"), ("gctronic-overo", "gctronic")])
def test_the_emulator_takes_the_old_names_too_with_a_warning(old: str, new: str) -> None:
    with pytest.warns(FutureWarning, match=f"{old!r} is deprecated"):
        assert firmware_name(old) == new
