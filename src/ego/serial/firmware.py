"""Which firmware answers: parsing the ASCII ``V``, ``C`` and ``b`` replies into a profile (no I/O).

docs/protocol.md, "Telling the firmwares apart": ``V\\n`` answers two lines, the version
(``v,Version 1.2.2 August 2008 GCtronic`` on the stock firmware, ``v,Version 1.5.3
November 2016 (Webots)`` on Webots') and ``HW version: %X``, a word of the dsPIC's EEPROM
in hex (``FFFF`` when never written); it says nothing of the robot's revision. On the
stock firmware ``C\\n`` answers ``c,N``, the selector position (10: Overo mode on
UART2; any other: Bluetooth on UART1), and ``b\\n`` answers ``b,RAW (P%)`` on an e-puck
revision 1.3 (which has a battery ADC) and ``b,FLAG`` on older ones: that is how the
revision is told, since the firmware itself detects it over I2C.

The e-puck2's main processor answers ``v,Version 2.0 January 2018 GCtronic`` and
``HW version: FFF7`` (MAIN:src/epuck1x/Asercom2.c:1543-1559; GCtronic's own monitor
tells the versions apart by the character after "Version ", MON:CommThread.cpp:111-129);
its ``C`` answers 8 over USB and 3 over Bluetooth (MAIN:src/main.c:214, 541).
"""

from __future__ import annotations

import re

from ego.errors import ProtocolError
from ego.seam.channel import FirmwareInfo
from ego.seam.profile import Command, Firmware, Profile
from ego.serial.pipuck import PIPUCK_PROFILES
from ego.serial.profiles import (
    EPUCK2_BLUETOOTH,
    EPUCK2_USB,
    EPUCK2_WIFI,
    GCTRONIC_BLUETOOTH,
    PROFILES,
)

__all__ = [
    "EPUCK2_BLUETOOTH_SELECTOR",
    "EPUCK2_WIFI_SELECTOR",
    "OVERO_SELECTOR",
    "FirmwareInfo",
    "epuck2_profile",
    "gctronic_profile",
    "identify",
    "is_epuck2",
    "is_gctronic",
    "is_rev13",
    "line_payload",
    "parse_hardware_version",
    "parse_selector",
    "profile_for",
]

#: The selector position in which the stock firmware talks to the Overo at 230400 baud.
OVERO_SELECTOR = 10
#: The e-puck2's selector position for asercom v2 over Bluetooth (MAIN:src/main.c:214).
EPUCK2_BLUETOOTH_SELECTOR = 3
#: The e-puck2's selector position for its radio's WiFi (MAIN:src/main.c:836-863).
EPUCK2_WIFI_SELECTOR = 15


def line_payload(line: str, command: str) -> str:
    """The text after ``x,`` of an ASCII reply to ``command`` (its lower-case letter)."""
    text = line.strip()
    prefix = command.lower() + ","
    if not text.startswith(prefix):
        raise ProtocolError(f"reply {text!r} to {command!r} does not start with {prefix!r}")
    return text[len(prefix) :]


def is_gctronic(version_line: str) -> bool:
    return "gctronic" in version_line.lower() and "webots" not in version_line.lower()


def is_epuck2(version_line: str) -> bool:
    """Whether a ``V`` payload is the e-puck2's asercom v2 ("Version 2.0 ... GCtronic")."""
    version_2 = re.match(r"\s*version\s+2\.", version_line, re.IGNORECASE)
    return is_gctronic(version_line) and version_2 is not None


def epuck2_profile(selector: int | None) -> Profile:
    """The e-puck2's profile for the link its selector says: 3 Bluetooth, 15 WiFi, else
    USB (8)."""
    if selector == EPUCK2_BLUETOOTH_SELECTOR:
        return EPUCK2_BLUETOOTH
    if selector == EPUCK2_WIFI_SELECTOR:
        return EPUCK2_WIFI
    return EPUCK2_USB


def profile_for(firmware: Firmware, selector: int | None, rev13: bool | None) -> Profile:
    """The profile of a robot known by what it said of itself (a served robot's welcome,
    a recording's metadata): its firmware, its selector position, its revision."""
    if firmware is Firmware.GCTRONIC:
        return gctronic_profile(selector, rev13)
    if firmware is Firmware.EPUCK2:
        return epuck2_profile(selector)
    if firmware in PIPUCK_PROFILES:  # a robot through a Pi-puck (ego.backends.pipuck)
        return PIPUCK_PROFILES[firmware]
    return PROFILES[firmware]


def parse_selector(line: str) -> int:
    """The selector position in a ``c,N`` reply (0..15)."""
    payload = line_payload(line, "C")
    if not re.fullmatch(r"\d{1,2}", payload) or int(payload) > 15:
        raise ProtocolError(f"selector reply {line.strip()!r} is not c,0..15")
    return int(payload)


def parse_hardware_version(line: str) -> int | None:
    """The EEPROM word of a ``HW version: %X`` line; None for a line of another shape."""
    match = re.fullmatch(r"HW version:\s*([0-9A-Fa-f]{1,4})", line.strip())
    return int(match.group(1), 16) if match else None


def is_rev13(battery_line: str | None) -> bool | None:
    """Whether the stock firmware's ``b`` reply is a revision 1.3's (``b,RAW (P%)``).

    Older robots answer ``b,0`` or ``b,1`` (the low-battery flag); None when nothing
    (or something else) answered.
    """
    if battery_line is None:
        return None
    text = battery_line.strip()
    if re.fullmatch(r"b,\d+ \(\d+%\)", text):
        return True
    if re.fullmatch(r"b,[01]", text):
        return False
    return None


def gctronic_profile(selector: int | None, rev13: bool | None) -> Profile:
    """The stock firmware's profile in a selector position, for a robot's revision.

    Selector 10 (or unknown: the Overo line is the one ego is made for) is Overo mode.
    A rev 1.3 e-puck's accelerometer sits on I2C: in Overo mode the firmware leaves I2C
    to the Overo and answers ``a``/``A`` with zeros, so they are removed; over Bluetooth
    it reads them with 0 g at 2048 and about 750 counts a g (docs/protocol.md, "a").
    """
    if selector is None or selector == OVERO_SELECTOR:
        profile = PROFILES[Firmware.GCTRONIC].but(rev13=rev13)
        if rev13:
            profile = profile.without(
                Command.ACCELEROMETER_RAW,
                Command.ACCELEROMETER_SPHERICAL,
                why="an e-puck rev 1.3, whose accelerometer is on I2C, answers a/A with zeros",
            )
        return profile
    profile = GCTRONIC_BLUETOOTH.but(
        description=f"{GCTRONIC_BLUETOOTH.description}, selector {selector}", rev13=rev13
    )
    if rev13:
        profile = profile.but(acc_zero_counts=2048, acc_counts_per_g=750)
    return profile


def identify(
    version_lines: list[str], selector: int | None = None, battery_line: str | None = None
) -> FirmwareInfo:
    """The profile for what ``V`` (and for the stock firmware, ``C`` and ``b``) answered.

    ``version_lines`` empty means nothing answered: the ``webots`` profile (Webots'
    firmware answers ``V``, but a robot that answers no ASCII at all is spoken to as one).
    """
    if not version_lines:
        return FirmwareInfo(PROFILES[Firmware.WEBOTS])
    version = line_payload(version_lines[0], "V")
    hardware = parse_hardware_version(version_lines[1]) if len(version_lines) > 1 else None
    if not is_gctronic(version):
        return FirmwareInfo(PROFILES[Firmware.WEBOTS], version, hardware, selector)
    if is_epuck2(version):
        return FirmwareInfo(epuck2_profile(selector), version, hardware, selector)
    profile = gctronic_profile(selector, is_rev13(battery_line))
    return FirmwareInfo(profile, version, hardware, selector)
