"""Which firmware answers: the V and C replies into a profile (protocol.md, "Firmware profile")."""

from __future__ import annotations

import pytest

from ego.errors import ProtocolError, UnsupportedDeviceError
from ego.seam.batch import Request
from ego.seam.profile import Command, Firmware
from ego.serial.firmware import (
    OVERO_SELECTOR,
    identify,
    is_gctronic,
    is_rev13,
    line_payload,
    parse_hardware_version,
    parse_selector,
)
from ego.serial.protocol import encode_batch

# docs/protocol.md, "V": Asercom.c sends "v,Version 1.2.2 August 2008 GCtronic" then
# sprintf("HW version: %X", HWversion), a word read from the EEPROM (0xFFFF when never
# written); Webots' firmware.c answers "v,Version 1.5.3 November 2016 (Webots)".
GCTRONIC = ["v,Version 1.2.2 August 2008 GCtronic", "HW version: FFFF"]
WEBOTS = ["v,Version 1.5.3 November 2016 (Webots)", "HW version: 1300"]
#: Asercom.c, ASCII 'b': "b,%d (%d%%)" on a rev 1.3 (raw ADC, percent), "b,%d" (BATT_LOW).
REV13_BATTERY, OLD_BATTERY = "b,3012 (76%)", "b,1"


def test_webots_firmware_gets_the_webots_profile() -> None:
    info = identify(WEBOTS)
    assert info.firmware is Firmware.WEBOTS
    assert info.version == "Version 1.5.3 November 2016 (Webots)"
    assert info.hardware_version == 0x1300
    assert info.profile.line_baud == 115200  # firmware.c: e_init_uart1(), 115200 only
    assert info.detected


@pytest.mark.parametrize(
    ("line", "word"),
    [("HW version: FFFF", 0xFFFF), ("HW version: 1300", 0x1300), ("HW version: 0", 0),
     ("HW version: 1.3", None), ("HW version: 12345", None), ("HW: 13", None)],
)  # fmt: skip
def test_the_hardware_version_is_an_eeprom_word_in_hex(line: str, word: int | None) -> None:
    """Never "1.3": the format is %X of a 16-bit word; anything else is not that line."""
    assert parse_hardware_version(line) == word


def test_gctronic_firmware_on_selector_10_gets_the_overo_profile() -> None:
    """Asercom.c: selector 10 talks to the Overo on UART2 (use_bt = 0)."""
    info = identify(GCTRONIC, selector=10, battery_line=OLD_BATTERY)
    assert info.firmware is Firmware.GCTRONIC
    assert info.selector == OVERO_SELECTOR == 10
    assert info.hardware_version == 0xFFFF
    assert info.profile.supports(Command.ACCELEROMETER_RAW)
    assert info.profile.reply_values(Command.PROXIMITY) == 10
    assert not info.profile.supports(Command.FLOOR)
    assert info.profile.line_baud == 230400
    assert info.profile.rev13 is False


@pytest.mark.parametrize("selector", [3, 0, 15])
def test_gctronic_firmware_on_another_selector_is_its_bluetooth_mode(selector: int) -> None:
    """Asercom.c: any other selector answers on UART1 (use_bt = 1): 8 IR values, and M
    with the ground and cliff sensors (CLIFF_SENSORS is defined)."""
    info = identify(GCTRONIC, selector=selector, battery_line=OLD_BATTERY)
    assert info.firmware is Firmware.GCTRONIC
    assert info.selector == selector
    assert info.profile.reply_values(Command.PROXIMITY) == 8
    assert info.profile.reply_values(Command.FLOOR) == 5
    assert info.profile.leds == tuple(range(10))
    assert info.profile.line_baud == 115200


def test_silence_gets_the_webots_profile() -> None:
    info = identify([])
    assert info.firmware is Firmware.WEBOTS
    assert info.version == ""


@pytest.mark.parametrize(
    ("line", "rev13"), [(REV13_BATTERY, True), (OLD_BATTERY, False), ("b,0", False),
                        (None, None), ("z,Command not found", None)]
)  # fmt: skip
def test_the_battery_reply_tells_a_rev_1_3(line: str | None, rev13: bool | None) -> None:
    assert is_rev13(line) is rev13


def test_a_rev_1_3_in_overo_mode_refuses_the_accelerometer() -> None:
    """Asercom.c, 'a' and 'A': in Overo mode isEpuckVersion1_3() gives zeros; a device the
    firmware cannot serve is refused, never read as zeros."""
    info = identify(GCTRONIC, selector=10, battery_line=REV13_BATTERY)
    assert info.profile.rev13 is True
    for letter in "aA":
        with pytest.raises(UnsupportedDeviceError, match=r"rev 1\.3"):
            encode_batch([Request(Command((-ord(letter)) & 0xFF))], info.profile)
    assert encode_batch([Request(Command.PROXIMITY)], info.profile).reply_size == 20


def test_a_rev_1_3_over_bluetooth_reads_its_accelerometer_at_2048() -> None:
    """e_acc.c, e_get_acc_filtered: a rev 1.3 gives ((v>>4) - (v>>6)) + 2048, about 750 a g."""
    info = identify(GCTRONIC, selector=3, battery_line=REV13_BATTERY)
    assert info.profile.supports(Command.ACCELEROMETER_RAW)
    assert (info.profile.acc_zero_counts, info.profile.acc_counts_per_g) == (2048, 750)
    older = identify(GCTRONIC, selector=3, battery_line=OLD_BATTERY)
    assert (older.profile.acc_zero_counts, older.profile.acc_counts_per_g) == (2000, 800)


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
