"""The e-puck1's register map through a Pi-puck (York's firmware), as data (no I/O).

York's dsPIC firmware for the Pi-puck (yorkrobotlab/pi-puck-e-puck1, docs/protocol.md,
"The Pi-puck") is an I2C slave at 0x1F (``i2c_slave.c:31``) holding 16-bit registers:
a write is the register number, then its low byte, then its high byte (the high byte
cleared when only one comes, ``i2c_slave.c:59-76``); a read sends the register's low
byte, then its high byte (``i2c_slave.c:78-87``). SMBus' word transfers are exactly that
(little-endian), so ego uses ``write_word_data``/``read_word_data`` as York's own
``pipuck`` library does (``python-library/pipuck/epuck.py:36-46``). The register pointer
does not advance: each register is its own transaction.

The map (README.md:27-41, applied in ``main.c:44-113``):

====  =====  ===  ============================================================
reg   bits   R/W  meaning
====  =====  ===  ============================================================
0     8      R/W  the ring's LEDs, bit i = LED i
1     8      R/W  bit 0 the front LED, bit 1 the body LED
2, 3  16     R/W  left, right speed, steps/s, signed; the firmware clamps to +-1000
4, 5  16     RO   left, right step counter, unsigned, wrapping at 65536
6     8      R/W  bit 0: the IR sensors measure (0 at power-on: they do not)
7-14  16     RO   IR proximity 0..7
15-22 16     RO   IR ambient 0..7
====  =====  ===  ============================================================
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Final

from ego.errors import OutOfRangeError

__all__ = [
    "ADDRESS",
    "AMBIENT",
    "IR_CONTROL",
    "LEDS_FRONT_BODY",
    "LEDS_RING",
    "PROXIMITY",
    "SPEED_LEFT",
    "SPEED_LIMIT",
    "SPEED_RIGHT",
    "STEPS_LEFT",
    "STEPS_RIGHT",
    "YorkState",
    "signed",
    "writes",
]

ADDRESS: Final = 0x1F
LEDS_RING: Final = 0
LEDS_FRONT_BODY: Final = 1
SPEED_LEFT: Final = 2
SPEED_RIGHT: Final = 3
STEPS_LEFT: Final = 4
STEPS_RIGHT: Final = 5
IR_CONTROL: Final = 6
#: The eight proximity registers, ps0..ps7.
PROXIMITY: Final = tuple(range(7, 15))
#: The eight ambient registers, ls0..ls7.
AMBIENT: Final = tuple(range(15, 23))
#: main.c:59-78: speeds beyond +-1000 are clamped by the firmware.
SPEED_LIMIT: Final = 1000
#: Register 1's bits (README.md:34: ``xxxxxxbf``).
FRONT_BIT: Final = 0x01
BODY_BIT: Final = 0x02


def signed(word: int) -> int:
    """A 16-bit register's value as int16 (a speed, a step counter's wrap)."""
    return word - 0x10000 if word & 0x8000 else word


@dataclass(frozen=True, slots=True)
class YorkState:
    """The writable registers as ego last set them."""

    ring: int = 0
    front_body: int = 0
    speed_left: int = 0
    speed_right: int = 0
    ir_on: bool = False

    def with_led(self, index: int, value: int) -> YorkState:
        """``L index value``: 0 off, 1 on, 2 and up toggles; 0..7 the ring, 8 the body, 9
        the front LED (ego's led8, led9)."""
        if not 0 <= index <= 9:
            raise OutOfRangeError(f"LED {index} is outside 0..9")
        if index < 8:
            return replace(self, ring=_set(self.ring, 1 << index, value))
        bit = BODY_BIT if index == 8 else FRONT_BIT
        return replace(self, front_body=_set(self.front_body, bit, value))

    def with_speeds(self, left: int, right: int) -> YorkState:
        for name, speed in (("left", left), ("right", right)):
            if not -SPEED_LIMIT <= speed <= SPEED_LIMIT:
                raise OutOfRangeError(f"{name} speed {speed} steps/s is outside +-{SPEED_LIMIT}")
        return replace(self, speed_left=left, speed_right=right)


def _set(bits: int, bit: int, value: int) -> int:
    on = not bits & bit if value > 1 else bool(value)
    return bits | bit if on else bits & ~bit


#: The register writes of each field: (register, is a word).
_FIELDS: Final = (
    ("ring", LEDS_RING, False),
    ("front_body", LEDS_FRONT_BODY, False),
    ("speed_left", SPEED_LEFT, True),
    ("speed_right", SPEED_RIGHT, True),
    ("ir_on", IR_CONTROL, False),
)


def writes(
    state: YorkState, before: YorkState | None
) -> list[tuple[int, int, bool]]:
    """The writes that bring the robot from ``before`` (None: unknown, write all) to
    ``state``: (register, value as sent, whether a word). A word's value is its 16 bits
    (a negative speed in two's complement); a byte register is written as one byte."""
    out: list[tuple[int, int, bool]] = []
    for name, register, word in _FIELDS:
        value = int(getattr(state, name))
        if before is not None and int(getattr(before, name)) == value:
            continue
        out.append((register, value & 0xFFFF if word else value, word))
    return out
