"""The e-puck2's main processor as the Pi-puck sees it: the I2C slave at 0x1F of the
firmware's "gumstix" mode (selector 10).

Written from e-puck2/e-puck2_main-processor, branch ``gumstix``,
@517ef07095b193ba7197895ba5c2cb8bf8c7fb2a, ``src/gumstix.c`` (cited as gumstix.c:N):

* 7-bit address 0x1F (gumstix.c:29, ``0x3E`` in 8-bit form), at 100 kHz (:39-45).
* The Pi writes 20 bytes (:31, :47-49): left, right speed (int16, little-endian),
  speaker, LED1/3/5/7 bits, LED2/4/6/8 RGB (12 bytes), settings, and an XOR of the 19
  bytes before it. The slave keeps them in a 20-byte buffer (:50, :62-63).
* When a write ends, ``messageProcessor`` (:111-160) copies the buffer, builds the
  47-byte reply from the sensors *then* (8 proximity, 8 ambient, 4 microphones as
  little-endian words, selector | button << 4, left and right steps as int16, the TV
  remote's data, an XOR of the 46 bytes) and arms it for the read that follows. A read
  with no write before it gets the reply already armed (:196-198; zeros at power-on).
* The main loop (:200-255) then checks the XOR (:208-213) and, only if it matches,
  applies the command (:214-246); a wrong XOR drops the whole command silently (:248-250),
  and the reply is sent either way.
* Speaker values 1..3 call ``play_melody(value - 1)`` (:217-219): a value held in
  every packet asks again every packet. Settings bit 0 calibrates the IR (:232-234),
  bit 1 is ignored (:235-239), bit 2 makes the two words step-counter values
  (``left_motor_set_pos``) instead of speeds (:240-246).
* Speeds are clamped to +-1100 steps/s (src/motors.c:195-200, src/motors.h:7); the
  step counters are int32 halved microsteps, sent as int16 (gumstix.c:143-148), so they
  wrap. This branch does not calibrate the IR at power-on (src/main.c:378-430), so the
  proximity values start uncalibrated.

What the sources do not settle [inferred]: bytes a write sends past the 20th are
acknowledged and dropped; a read past the 47th byte gets 0xFF (the bus's pull-ups);
an empty write does not call ``messageProcessor``; the command is applied at the
transaction's stop.
"""

from __future__ import annotations

import struct
from collections import deque
from dataclasses import dataclass, field

from firmware_sim.epuck2.motors import int16
from firmware_sim.epuck2.robot import SOUNDS, Epuck2Robot

__all__ = ["ACTUATORS_SIZE", "GUMSTIX_ADDRESS", "SENSORS_SIZE", "Command", "GumstixMcu", "xor"]

GUMSTIX_ADDRESS = 0x1F
ACTUATORS_SIZE = 19 + 1
SENSORS_SIZE = 46 + 1
#: src/main.c:178: the gumstix mode's selector position.
GUMSTIX_SELECTOR = 10


def xor(data: bytes | bytearray) -> int:
    """The longitudinal redundancy check both ends append (gumstix.c:151-156, 208-212)."""
    check = 0
    for byte in data:
        check ^= byte
    return check


@dataclass(frozen=True, slots=True)
class Command:
    """A 20-byte actuator packet as the firmware reads it (gumstix.c:214-246)."""

    left: int
    right: int
    speaker: int
    red: tuple[bool, bool, bool, bool]
    rgb: tuple[tuple[int, int, int], ...]
    settings: int
    valid: bool

    @classmethod
    def parse(cls, packet: bytes) -> Command:
        left, right = struct.unpack_from("<hh", packet)
        rgb = tuple(tuple(packet[6 + 3 * i : 9 + 3 * i]) for i in range(4))
        red = tuple(bool(packet[5] >> i & 1) for i in range(4))
        return cls(left, right, packet[4], red, rgb, packet[18],  # type: ignore[arg-type]
                   valid=xor(packet[:19]) == packet[19])  # fmt: skip

    @property
    def is_stop(self) -> bool:
        """A valid speed command of 0, 0 with every LED off and no sound."""
        return (self.valid and self.left == 0 and self.right == 0 and not self.settings & 4
                and not any(self.red) and not any(map(any, self.rgb))
                and not 1 <= self.speaker <= 3)  # fmt: skip


@dataclass(slots=True)
class GumstixRecord:
    """What the main processor received and did (ground truth for tests)."""

    packets: int = 0
    checksum_errors: int = 0
    last: Command | None = None
    last_valid: Command | None = None
    #: Melodies asked for, by name, in order (one per packet that asked).
    sounds: list[str] = field(default_factory=list)
    #: Every packet's raw 20 bytes (the last 10,000).
    raw: deque[bytes] = field(default_factory=lambda: deque(maxlen=10_000))


class GumstixMcu:
    """The slave at 0x1F over an :class:`Epuck2Robot` (an I2C ``Target``)."""

    address = GUMSTIX_ADDRESS

    def __init__(self, robot: Epuck2Robot) -> None:
        self.robot = robot
        robot.selector = GUMSTIX_SELECTOR
        robot.proximity.forget_calibration()
        self._rx = bytearray(ACTUATORS_SIZE)
        self._work = bytes(ACTUATORS_SIZE)
        self._tx = bytearray(SENSORS_SIZE)
        self._write_pending = False
        self._processed = False
        self.record = GumstixRecord()
        #: Faults for the next read: flip the reply's checksum; cut it after n bytes.
        self.corrupt_next = 0
        self.short_next: int | None = None

    # -- the I2C slave (Target) -----------------------------------------------------

    def write(self, data: bytes) -> None:
        if not data:
            return
        body = data[:ACTUATORS_SIZE]
        self._rx[: len(body)] = body
        self._write_pending = True

    def read(self, count: int) -> bytes:
        if self._write_pending:
            self._message_processor()
        reply = bytearray(self._tx)
        if self.corrupt_next > 0:
            self.corrupt_next -= 1
            reply[-1] ^= 0xFF
        if self.short_next is not None:
            cut, self.short_next = self.short_next, None
            reply[cut:] = b"\xff" * (len(reply) - cut)
        return bytes(reply[:count]).ljust(count, b"\xff")

    def stop(self) -> None:
        if self._write_pending:
            self._message_processor()
        if self._processed:
            self._processed = False
            self._main_loop()

    # -- gumstix.c ------------------------------------------------------------------

    def _message_processor(self) -> None:
        """gumstix.c:111-160: take the command, build the reply from the sensors now."""
        self._write_pending = False
        self._work = bytes(self._rx)
        self._processed = True
        robot = self.robot
        prox, ambient = robot.proximity.sample()
        words = [*prox, *ambient, *robot.microphones.volumes()]
        tx = bytearray(struct.pack("<20H", *(w & 0xFFFF for w in words)))
        tx.append((robot.selector & 0x0F) | (0x10 if robot.button else 0))
        left, right = robot.steps()
        tx += struct.pack("<hh", int16(left), int16(right))
        tx.append(robot.rc5[2] & 0xFF)
        tx.append(xor(tx))
        self._tx = tx

    def _main_loop(self) -> None:
        """gumstix.c:208-250: check the XOR; apply the command only if it matches."""
        command = Command.parse(self._work)
        record = self.record
        record.packets += 1
        record.last = command
        record.raw.append(self._work)
        if not command.valid:
            record.checksum_errors += 1
            return
        record.last_valid = command
        robot = self.robot
        if 1 <= command.speaker <= 3:
            robot.play(command.speaker)  # play_melody(MARIO + value - 1)
            record.sounds.append(SOUNDS[command.speaker])
        for i, on in enumerate(command.red):
            robot.leds.set_led(i, int(on))
        for i, (r, g, b) in enumerate(command.rgb):
            robot.leds.set_rgb_led(i, r, g, b)
        if command.settings & 0x01:
            robot.proximity.calibrate()
        if command.settings & 0x04:
            robot.set_steps(command.left, command.right)
        else:
            robot.set_speeds(command.left, command.right)
