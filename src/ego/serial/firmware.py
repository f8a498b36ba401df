"""Which firmware answers: parsing the ASCII ``V`` and ``C`` replies into a profile (no I/O).

protocol.md: ``V\\n`` answers two lines, ``v,Version 1.2.2 August 2008 GCtronic`` /
``HW version: ...`` (stock firmware) or ``v,Version 1.5.3 November 2016 (Webots)``.
For the stock GCtronic firmware ``C\\n`` answers ``c,N``, the selector position;
10 is the Overo mode. The Webots firmware, and one that answers neither, get the
``thesis`` profile.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from ego.errors import ProtocolError
from ego.serial.protocol import PROFILES, Command, Firmware, Profile

__all__ = [
    "OVERO_SELECTOR",
    "FirmwareInfo",
    "identify",
    "is_gctronic",
    "line_payload",
    "parse_selector",
]

#: The selector position in which the stock firmware talks to the Overo at 230400 baud.
OVERO_SELECTOR = 10


@dataclass(frozen=True, slots=True)
class FirmwareInfo:
    """The profile in use and what the firmware said of itself."""

    profile: Profile
    version: str = ""
    hardware: str = ""
    selector: int | None = None
    #: False when the profile was given explicitly rather than probed.
    detected: bool = True

    @property
    def firmware(self) -> Firmware:
        return self.profile.firmware


def line_payload(line: str, command: str) -> str:
    """The text after ``x,`` of an ASCII reply to ``command`` (its lower-case letter)."""
    text = line.strip()
    prefix = command.lower() + ","
    if not text.startswith(prefix):
        raise ProtocolError(f"reply {text!r} to {command!r} does not start with {prefix!r}")
    return text[len(prefix) :]


def is_gctronic(version_line: str) -> bool:
    return "gctronic" in version_line.lower() and "webots" not in version_line.lower()


def parse_selector(line: str) -> int:
    """The selector position in a ``c,N`` reply (0..15)."""
    payload = line_payload(line, "C")
    if not re.fullmatch(r"\d{1,2}", payload) or int(payload) > 15:
        raise ProtocolError(f"selector reply {line.strip()!r} is not c,0..15")
    return int(payload)


def identify(version_lines: list[str], selector: int | None = None) -> FirmwareInfo:
    """The profile for what ``V`` (and for stock firmware, ``C``) answered.

    ``version_lines`` empty means nothing answered: the ``thesis`` profile, as
    protocol.md says for a firmware that answers neither.
    """
    if not version_lines:
        return FirmwareInfo(PROFILES[Firmware.WEBOTS])
    version = line_payload(version_lines[0], "V")
    hardware = version_lines[1].strip() if len(version_lines) > 1 else ""
    if not (is_gctronic(version) and selector == OVERO_SELECTOR):
        return FirmwareInfo(PROFILES[Firmware.WEBOTS], version, hardware, selector)
    profile = PROFILES[Firmware.GCTRONIC]
    if re.search(r"\b1\.3\b", hardware):
        # protocol.md: on hardware revision 1.3 the accelerometer is on I2C, so the
        # stock firmware returns zeros for a/A; refuse the device instead.
        profile = profile.without(
            Command.ACCELEROMETER_RAW,
            Command.ACCELEROMETER_SPHERICAL,
            why="hardware 1.3 (accelerometer on the Overo's I2C bus)",
        )
    return FirmwareInfo(profile, version, hardware, selector)
