"""The e-puck2's I2C packet through a Pi-puck, as bytes and values (no I/O).

GCtronic's e-puck2 main processor, branch ``gumstix`` (docs/protocol.md, "The Pi-puck"),
in selector 10 is an I2C slave at 0x1F (``src/gumstix.c:28-29``, 0x3E the 8-bit form).
The Pi writes 20 bytes and, in the same combined transaction, reads 47
(``gumstix.c:31-32``; GCtronic's ``e-puck2/e-puck2_test.py:18-27`` and epuck_ros2's
driver do the same). Each message ends in the XOR of the bytes before it (an LRC):

* the firmware drops a written message whose checksum is wrong (``gumstix.c:208-250``);
* the reply's is computed over its first 46 bytes (``gumstix.c:151-156``), and ego
  refuses a reply whose checksum is wrong (:class:`~ego.errors.ChecksumError`).

Actuators, 20 bytes (``gumstix.c:47-49, 214-246``): left and right speed as int16
little-endian (low byte first, ``gumstix.c:214-215``); the speaker (1..3 play melody
0..2, anything else nothing, ``gumstix.c:217-219``); the red LEDs LED1, LED3, LED5,
LED7 as bits 0..3; LED2, LED4, LED6, LED8 as R, G, B each 0..100 (``set_rgb_led``);
the settings byte (bit 0 calibrate the IR sensors, bit 1 obstacle avoidance, which the
firmware ignores, bit 2: bytes 0..3 set the step counters instead of the speeds,
``gumstix.c:232-246``); the checksum.

Sensors, 47 bytes (``gumstix.c:53-55, 122-149``): eight calibrated proximity values,
eight ambient values and four microphone volumes, each 16 bits little-endian (the
firmware writes ``n & 0xff`` then ``n >> 8`` of an ``int16_t``; ego reads the volumes
unsigned, the rest signed); the selector in the low
nibble of byte 40 and the button in its bit 4; the left and right step counters, int16
little-endian (they wrap at +-32768, ``left_motor_get_pos`` cast to int16); the TV
remote's last data; the checksum.
"""

from __future__ import annotations

import struct
from dataclasses import dataclass
from functools import reduce
from operator import xor
from typing import Final

from ego.errors import ChecksumError, OutOfRangeError, ShortReplyError

__all__ = [
    "ACTUATORS_SIZE",
    "ADDRESS",
    "SENSORS_SIZE",
    "ActuatorPacket",
    "SensorReply",
    "Settings",
    "checksum",
    "decode_sensors",
    "encode_actuators",
]

#: The e-puck2's 7-bit address on the robot's I2C bus (gumstix.c:29: 0x3E >> 1).
ADDRESS: Final = 0x1F
#: 19 bytes of data and the checksum (gumstix.c:31).
ACTUATORS_SIZE: Final = 20
#: 46 bytes of data and the checksum (gumstix.c:32).
SENSORS_SIZE: Final = 47
#: The speeds the firmware drives (MAIN:src/motors.h MOTOR_SPEED_LIMIT): what the field
#: can mean; ego's motors refuse more before a value gets here.
SPEED_LIMIT: Final = 1100
#: The melodies byte 4 plays: 1..3 (gumstix.c:217).
MELODIES: Final = (1, 2, 3)

_ACTUATORS: Final = struct.Struct("<hhBB12BB")
_SENSORS: Final = struct.Struct("<8h8h4HBhhB")


class Settings:
    """The bits of the actuators' settings byte (gumstix.c:232-246)."""

    CALIBRATE_PROXIMITY: Final = 0x01
    OBSTACLE_AVOIDANCE: Final = 0x02
    SET_STEP_COUNTERS: Final = 0x04


def checksum(data: bytes) -> int:
    """The XOR of every byte of ``data`` (the packets' LRC)."""
    return reduce(xor, data, 0)


Rgb = tuple[int, int, int]


@dataclass(frozen=True, slots=True)
class ActuatorPacket:
    """What one 20-byte message says. ``sound`` and ``settings`` are one-shots: a
    message carrying them goes once (the firmware replays a melody on every message
    whose byte 4 is 1..3)."""

    speed_left: int = 0
    speed_right: int = 0
    #: LED1, LED3, LED5, LED7 (ego's led0, led2, led4, led6).
    red_leds: tuple[bool, bool, bool, bool] = (False, False, False, False)
    #: LED2, LED4, LED6, LED8 (ego's led1, led3, led5, led7), R, G, B in percent.
    rgb_leds: tuple[Rgb, Rgb, Rgb, Rgb] = ((0, 0, 0), (0, 0, 0), (0, 0, 0), (0, 0, 0))
    sound: int = 0
    settings: int = 0


def encode_actuators(packet: ActuatorPacket) -> bytes:
    """The 20 bytes of ``packet``, its checksum last; OutOfRangeError for a value the
    message cannot carry (a speed beyond the firmware's limit, a colour over 100 %)."""
    for name, speed in (("left", packet.speed_left), ("right", packet.speed_right)):
        limit = 32767 if packet.settings & Settings.SET_STEP_COUNTERS else SPEED_LIMIT
        if not -limit <= speed <= limit:
            raise OutOfRangeError(f"{name} speed {speed} steps/s is outside +-{limit}")
    colours = [c for rgb in packet.rgb_leds for c in rgb]
    for value in colours:
        if not 0 <= value <= 100:
            raise OutOfRangeError(f"RGB LED value {value} % is outside 0..100")
    if packet.sound not in (0, *MELODIES):
        raise OutOfRangeError(f"sound {packet.sound} is not a melody the packet plays (1..3)")
    if not 0 <= packet.settings <= 0xFF:
        raise OutOfRangeError(f"settings 0x{packet.settings:X} do not fit a byte")
    leds = sum(1 << i for i, on in enumerate(packet.red_leds) if on)
    data = _ACTUATORS.pack(
        packet.speed_left, packet.speed_right, packet.sound, leds, *colours, packet.settings
    )
    return data + bytes([checksum(data)])


@dataclass(frozen=True, slots=True)
class SensorReply:
    """The 47-byte reply, decoded."""

    proximity: tuple[int, ...]
    ambient: tuple[int, ...]
    microphones: tuple[int, ...]
    selector: int
    button: bool
    steps: tuple[int, int]
    tv_remote: int


def decode_sensors(reply: bytes) -> SensorReply:
    """The values of a 47-byte reply; ShortReplyError for another length, ChecksumError
    when its last byte is not the XOR of the others (it never reaches a controller)."""
    if len(reply) != SENSORS_SIZE:
        raise ShortReplyError(f"the e-puck2 answered {len(reply)} bytes, not {SENSORS_SIZE}")
    expected = checksum(reply[:-1])
    if reply[-1] != expected:
        raise ChecksumError(
            f"the e-puck2's reply checksum is 0x{reply[-1]:02X}, its bytes give 0x{expected:02X}"
        )
    values = _SENSORS.unpack(reply[:-1])
    flags = values[20]
    return SensorReply(
        proximity=values[0:8],
        ambient=values[8:16],
        microphones=values[16:20],
        selector=flags & 0x0F,
        button=bool(flags & 0x10),
        steps=(values[21], values[22]),
        tv_remote=values[23],
    )
