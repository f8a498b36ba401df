"""The vocabulary of the seam: the dsPIC's commands, its firmwares and what each serves.

A :class:`Profile` says what one firmware serves (each command's wire format, its LEDs,
its line rate and timings): what a Robot, its device families and every channel agree on,
whatever carries the batches (a serial line, ``ego serve``, Zenoh, a recording). The
profiles themselves, and the encoding of batches, are the serial protocol's
(:mod:`ego.serial.protocol`, which re-exports these names).
"""

from __future__ import annotations

import enum
import struct
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from types import MappingProxyType
from typing import Any

from ego.errors import OutOfRangeError, UnsupportedDeviceError

__all__ = [
    "DEFAULT_BAUD",
    "FIRMWARE_CHOICES",
    "AsciiStop",
    "Command",
    "Firmware",
    "Profile",
    "WireFormat",
]

#: The Overo's UART to the dsPIC (docs/protocol.md, Line).
DEFAULT_BAUD = 230400


class Command(enum.IntEnum):
    """Wire bytes of the binary commands (docs/protocol.md, thesis Table 4.1)."""

    ACCELEROMETER_RAW = 0x9F  # a
    ACCELEROMETER_SPHERICAL = 0xBF  # A
    SET_SPEED = 0xBC  # D
    GET_SPEED = 0xBB  # E
    SET_LED = 0xB4  # L
    FLOOR = 0xB3  # M
    PROXIMITY = 0xB2  # N
    LIGHT = 0xB1  # O
    SET_STEPS = 0xB0  # P
    GET_STEPS = 0xAF  # Q
    MIC_AMPLITUDE = 0x8B  # u
    MIC_BUFFER = 0xAB  # U
    BATTERY = 0x9E  # b
    # The e-puck2's asercom v2 adds commands below 'A' (docs/protocol.md, "e-puck2"):
    # their bytes are -0x08 .. -0x11, and the gyro's is the e-puck1 letter 'g'.
    GYRO_RAW = 0x99  # g
    ALL_SENSORS = 0xF8  # -0x08: the 103-byte sensor packet (ego.serial.asercom2)
    ALL_ACTUATORS = 0xF7  # -0x09: the 19-byte actuator payload
    RGB_LEDS = 0xF6  # -0x0A: 12 bytes, LED2/4/6/8 as R,G,B in percent
    BUTTON = 0xF5  # -0x0B
    MICROPHONES_4 = 0xF4  # -0x0C: the four microphones' amplitudes
    TOF = 0xF3  # -0x0D: the VL53L0X's distance in mm
    SD_STATE = 0xF2  # -0x0E
    MAGNETOMETER_ENABLE = 0xF1  # -0x0F
    PROXIMITY_MODE = 0xF0  # -0x10
    TOF_ENABLE = 0xEF  # -0x11
    END = 0x00

    @property
    def letter(self) -> str:
        """The ASCII letter this command is the negative of ('' for END; the e-puck2's
        commands below 'A' have none: their hex byte, "-0x08")."""
        if not self.value:
            return ""
        code = (-self.value) & 0xFF
        return chr(code) if code >= 0x20 else f"-0x{code:02X}"


class Firmware(str, enum.Enum):
    """Which dsPIC firmware answers, named after the firmware it is (docs/protocol.md, Line).

    ``gctronic`` is GCtronic's stock asercom: in selector position 10 it talks to the
    Overo on UART2 at 230400 baud (the line ego is made for); in other positions it also
    answers over Bluetooth. ``webots`` is Webots' e-puck firmware 1.5.x, which listens
    only on UART1, the Bluetooth line, at 115200 baud.
    """

    GCTRONIC = "gctronic"
    WEBOTS = "webots"
    #: GCtronic's e-puck2 main processor running asercom v2 (selector 8 over USB, 3 over
    #: Bluetooth): ``V`` answers ``v,Version 2.0 ... GCtronic`` (docs/protocol.md, "e-puck2").
    EPUCK2 = "epuck2"
    #: The e-puck2's main processor in its I2C mode for a Pi-puck (selector 10, GCtronic's
    #: ``gumstix`` branch): one 20-byte write and one 47-byte read a step, each with an XOR
    #: checksum (docs/protocol.md, "The Pi-puck"; ego.backends.pipuck).
    EPUCK2_I2C = "epuck2-i2c"
    #: York's e-puck1 firmware for the Pi-puck: SMBus byte and word registers at 0x1F
    #: (docs/protocol.md, "The Pi-puck"; ego.backends.pipuck).
    YORK = "york"

    def __str__(self) -> str:
        return self.value

    @classmethod
    def choose(cls, name: Firmware | str | None) -> Firmware | None:
        """The firmware a user named; None for "auto" (probe it). Refuses unknown names."""
        if name is None or name == "auto":
            return None
        try:
            return cls(name)
        except ValueError:
            choices = ", ".join(["auto", *(f.value for f in cls)])
            raise OutOfRangeError(f"firmware {name!r} is not one of {choices}") from None


#: The firmware names a user may give, "auto" first.
FIRMWARE_CHOICES = ("auto", "gctronic", "webots", "epuck2")


_NONE = struct.Struct("")


@dataclass(frozen=True, slots=True)
class WireFormat:
    """How one command travels: its arguments, its in-batch reply, and bytes it sends first."""

    arguments: struct.Struct = _NONE
    reply: struct.Struct = _NONE
    #: Bytes sent at once when the command is parsed, before the batch's replies (``U``).
    prefix: struct.Struct = _NONE
    #: Checks the reply's bytes (a ProtocolError for bytes the firmware never sends), where
    #: the command has such a check: the e-puck2's ``-0x08`` (docs/protocol.md).
    check: Callable[[memoryview], object] | None = None


@dataclass(frozen=True, slots=True)
class AsciiStop:
    """What the ASCII ``S`` command does on one firmware (docs/protocol.md, quirk "S")."""

    #: The LEDs it switches off.
    leds: tuple[int, ...]
    #: Whether it also sets the speeds ``E`` echoes back to (0, 0).
    clears_echo: bool


@dataclass(frozen=True, slots=True)
class Profile:
    """What one firmware serves: its commands' wire formats, LEDs, line rate and timings."""

    firmware: Firmware
    commands: Mapping[Command, WireFormat] = field(repr=False)
    leds: tuple[int, ...] = field(repr=False)
    #: Free text for error messages ("stock GCtronic asercom, selector 10").
    description: str = ""
    #: The rate of the UART this firmware answers on: it never answers faster, whatever
    #: rate the port was opened at (a pty carries any rate), so reply timeouts use it.
    line_baud: int = DEFAULT_BAUD
    #: Time the dsPIC spends on a command before its reply bytes can go out (an I2C read,
    #: software floating point); commands not listed take a few microseconds.
    work_s: Mapping[Command, float] = field(default_factory=dict, repr=False)
    #: How long the ASCII ``K`` (IR calibration) keeps the dsPIC deaf to the line.
    calibration_s: float = 1.0
    ascii_stop: AsciiStop = field(default=AsciiStop(tuple(range(8)), False), repr=False)
    #: 0 g of the raw accelerometer (``a``) and counts per g (docs/protocol.md, quirk "a").
    acc_zero_counts: int = 2000
    acc_counts_per_g: int = 800
    #: An e-puck revision 1.3 (I2C accelerometer, battery ADC); None when not asked.
    rev13: bool | None = field(default=None, compare=False)
    #: The commands whose devices this firmware leaves on the Overo's own I2C bus, with the
    #: chip that serves each there (ego.i2c.chips.CHIPS): the families read them over
    #: i2c-dev where the line does not (docs/protocol.md, "The Overo's own I2C bus").
    i2c: Mapping[Command, str] = field(default_factory=dict, repr=False)
    #: The fastest speed the firmware drives a wheel at, in steps/s: ego refuses more.
    max_speed_steps: int = 1000
    #: The maxVelocity of Webots' model of this robot's motors, rad/s, where it exceeds
    #: what the firmware drives (the e-puck2's PROTO: 7.536); None: the firmware's limit.
    model_max_velocity_rad_s: float | None = None
    #: The LEDs that are RGB (set by ``RGB_LEDS`` as percentages, in this order); the
    #: others are on/off through ``L``.
    rgb_leds: tuple[int, ...] = field(default=(), repr=False)
    #: The commands whose replies the "all sensors" packet (``ALL_SENSORS``) also holds,
    #: each with the function taking its values out of the packet's: a batch may ask the
    #: packet instead (ego.serial.protocol.encode_batch, by :attr:`cost_s`).
    all_sensors: Mapping[Command, Callable[[Sequence[float]], tuple[float, ...]]] = field(
        default_factory=dict, repr=False
    )

    def supports(self, command: Command) -> bool:
        return command is Command.END or command in self.commands

    def wire_format(self, command: Command) -> WireFormat:
        try:
            return self.commands[command]
        except KeyError:
            raise UnsupportedDeviceError(
                f"the {self.firmware} firmware ({self.description}) cannot serve command "
                f"{command.letter!r} ({command.name.lower()})"
            ) from None

    def reply_values(self, command: Command) -> int:
        """How many values the in-batch reply to ``command`` holds (0 if not served)."""
        if command not in self.commands:
            return 0
        return len(self.commands[command].reply.unpack(bytes(self.commands[command].reply.size)))

    def cost_s(self, command: Command) -> float:
        """What ``command`` adds to a batch's round trip: its bytes both ways at the line
        rate, and the firmware's work on it (:attr:`work_s`)."""
        fmt = self.wire_format(command)
        size = 1 + fmt.arguments.size + fmt.prefix.size + fmt.reply.size
        return size * 10 / self.line_baud + self.work_s.get(command, 0.0)

    def without(self, *commands: Command, why: str) -> Profile:
        """The same profile with some commands removed (a hardware revision's quirk)."""
        kept = {c: f for c, f in self.commands.items() if c not in commands}
        return replace(
            self, commands=MappingProxyType(kept), description=f"{self.description}; {why}"
        )

    def but(self, **changes: Any) -> Profile:
        """The same profile with some fields changed (a mode or a revision of the robot)."""
        return replace(self, **changes)
