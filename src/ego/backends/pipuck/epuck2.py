"""The e-puck2's side of a Pi-puck: ego's requests folded into the 20-byte message, and
each step's one combined transaction (write 20, read 47) with its retries.

What the firmware asks of its master (docs/protocol.md, "The Pi-puck"), and where it is
met here:

* every message's checksum right, or it is dropped: :func:`encode_actuators`;
* each reply's checksum checked: a wrong one, or a failed transfer, is retried
  (:data:`ATTEMPTS` in all), then raised as a typed error, never handed on;
* the speaker's byte plays a melody on *every* message that carries it, and settings
  bits 0 and 2 act on every message too: each such one-shot goes in exactly one message,
  and a retry carries the actuators' state without it [so a one-shot whose message was
  corrupted on the way in is lost rather than repeated];
* setting the step counters uses bytes 0-3 and leaves the speeds alone
  (``gumstix.c:240-246``): it is a message of its own, followed by the speeds.
"""

from __future__ import annotations

import logging
from dataclasses import replace
from typing import Final

from ego.backends.pipuck.bus import RobotBus, i2c_failure
from ego.backends.pipuck.packet import (
    ADDRESS,
    SENSORS_SIZE,
    ActuatorPacket,
    SensorReply,
    Settings,
    decode_sensors,
    encode_actuators,
)
from ego.errors import (
    LinkTimeoutError,
    OutOfRangeError,
    ProtocolError,
    UnsupportedDeviceError,
)
from ego.seam.batch import Request
from ego.seam.profile import Command, Profile
from ego.serial.pipuck import EPUCK2_I2C_PROFILE

__all__ = ["ATTEMPTS", "Epuck2Side", "fold"]

log = logging.getLogger(__name__)

#: Transfers of one message before its error is raised.
ATTEMPTS: Final = 3
#: The firmware's melodies by ego's sound numbers: T,1..3 (Mario, Underworld, Star Wars)
#: are the packet's 1..3 (``play_melody(n - 1)``, gumstix.c:217-219).
MELODIES: Final = (1, 2, 3)


def _led(state: ActuatorPacket, index: int, value: int) -> ActuatorPacket:
    """``L index value`` (0 off, 1 on, 2 and up toggles): even indices are LED1, 3, 5,
    7 (on/off), odd ones LED2, 4, 6, 8, whose red goes to 100 % (white would be a guess)."""
    if not 0 <= index <= 7:
        raise UnsupportedDeviceError(
            f"LED {index}: the e-puck2's I2C packet has LED1..LED8 only (ego's led0..led7); "
            "its body and front LEDs are served over USB (selector 8) or Bluetooth (3)"
        )
    if index % 2 == 0:
        red = list(state.red_leds)
        red[index // 2] = not red[index // 2] if value > 1 else bool(value)
        return replace(state, red_leds=(red[0], red[1], red[2], red[3]))
    rgb = list(state.rgb_leds)
    on = rgb[index // 2] == (0, 0, 0) if value > 1 else bool(value)
    rgb[index // 2] = (100, 0, 0) if on else (0, 0, 0)
    return replace(state, rgb_leds=(rgb[0], rgb[1], rgb[2], rgb[3]))


def fold(state: ActuatorPacket, request: Request) -> tuple[ActuatorPacket, ActuatorPacket | None]:
    """``request`` (a setter) applied to ``state``: the new state, and a one-shot message
    to send first (the step counters'), or None."""
    command, args = request.command, request.arguments
    if command is Command.SET_SPEED:
        return replace(state, speed_left=args[0], speed_right=args[1]), None
    if command is Command.SET_LED:
        return _led(state, args[0], args[1]), None
    if command is Command.RGB_LEDS:
        rgb = tuple((args[i], args[i + 1], args[i + 2]) for i in range(0, 12, 3))
        return replace(state, rgb_leds=(rgb[0], rgb[1], rgb[2], rgb[3])), None
    if command is Command.SET_STEPS:
        counters = replace(state, speed_left=args[0], speed_right=args[1],
                           settings=Settings.SET_STEP_COUNTERS)  # fmt: skip
        return state, counters
    raise UnsupportedDeviceError(f"{command.name.lower()} is not an actuator of the packet")


class Epuck2Side:
    """The e-puck2 at 0x1F on ``bus``: its actuators' state and its newest reply."""

    profile: Profile = EPUCK2_I2C_PROFILE
    #: The getters the packet answers (GET_SPEED: the speeds a valid reply confirmed).
    answers: frozenset[Command] = frozenset({
        Command.PROXIMITY, Command.LIGHT, Command.GET_STEPS, Command.MIC_AMPLITUDE,
        Command.MICROPHONES_4, Command.BUTTON, Command.ALL_SENSORS, Command.GET_SPEED,
    })  # fmt: skip

    def __init__(self, bus: RobotBus, name: str) -> None:
        self.bus = bus
        self.name = name
        self.state = ActuatorPacket()
        self._sent: ActuatorPacket | None = None
        self._one_shots: list[ActuatorPacket] = []
        self.reply: SensorReply | None = None
        self.retries = 0

    # -- the requests ---------------------------------------------------------------------

    def fold(self, request: Request) -> None:
        state, first = fold(self.state, request)
        encode_actuators(state)  # refuse now what the message cannot carry
        self.state = state
        if first is not None:
            self._one_shots.append(first)

    def play(self, number: int) -> None:
        """ASCII ``T,n``: melody ``n`` (1..3) in the next message, once."""
        if number not in MELODIES:
            raise UnsupportedDeviceError(
                f"sound {number}: the e-puck2's I2C packet plays the melodies 1..3 only "
                "(no tones, no stop); USB (selector 8) and Bluetooth (3) serve the rest"
            )
        self._one_shots.append(replace(self.state, sound=number))
        self.sync()

    def calibrate(self) -> None:
        """Settings bit 0: the firmware calibrates its IR sensors (calibrate_ir)."""
        self._one_shots.append(replace(self.state, settings=Settings.CALIBRATE_PROXIMITY))
        self.sync()

    # -- the bus ------------------------------------------------------------------------------

    def sync(self, getters: tuple[Command, ...] = ()) -> None:
        """Send each one-shot, then the state if it changed or ``getters`` need a reply."""
        while self._one_shots:
            self._transfer(self._one_shots[0])
            self._one_shots.pop(0)
        if getters or self.state != self._sent:
            self._transfer(self.state)

    def _transfer(self, packet: ActuatorPacket) -> None:
        message = encode_actuators(packet)
        error: Exception | None = None
        for attempt in range(ATTEMPTS):
            try:
                raw = self.bus.transaction(ADDRESS, message, SENSORS_SIZE)
                self.reply = decode_sensors(raw)
            except ProtocolError as exc:
                error = exc if self.name in str(exc) else type(exc)(f"{self.name}: {exc}")
            except OSError as exc:
                error = LinkTimeoutError(i2c_failure(exc, f"{self.name}: the e-puck2 at 0x1F"))
            else:
                if not packet.settings & Settings.SET_STEP_COUNTERS:  # it sets no speed
                    self._sent = replace(packet, sound=0, settings=0)
                return
            self.retries += 1
            log.warning("%s (attempt %d of %d)", error, attempt + 1, ATTEMPTS)
            message = encode_actuators(replace(packet, sound=0, settings=0)
                                       if not packet.settings & Settings.SET_STEP_COUNTERS
                                       else packet)  # fmt: skip
        assert error is not None
        raise error

    def answer(self, command: Command) -> tuple[int, ...]:
        """The values of ``command`` from the newest reply."""
        reply = self.reply
        if reply is None:
            raise ProtocolError(f"{self.name}: no reply from the e-puck2 yet")
        if command is Command.GET_SPEED:
            sent = self._sent or ActuatorPacket()
            return (sent.speed_left, sent.speed_right)
        found = {
            Command.PROXIMITY: reply.proximity,
            Command.LIGHT: reply.ambient,
            Command.GET_STEPS: reply.steps,
            Command.MIC_AMPLITUDE: reply.microphones[:3],
            Command.MICROPHONES_4: reply.microphones,
            Command.BUTTON: (1 if reply.button else 0,),
        }.get(command)
        if found is not None:
            return tuple(found)
        if command is Command.ALL_SENSORS:
            return _usb_packet(reply)
        raise OutOfRangeError(f"the e-puck2's packet has no {command.name.lower()}")

    def stop_message(self) -> None:
        """Zero speeds, every LED off, no one-shot: sent at close, whatever ego believes."""
        self._one_shots.clear()
        self.state = ActuatorPacket()
        self._transfer(self.state)


def _usb_packet(reply: SensorReply) -> tuple[int, ...]:
    """The USB "all sensors" packet's 49 values, with what the I2C packet holds (ego's
    selector family reads its field 41); every other field 0 (the families that read
    those are refused on this firmware: the magnetometer needs -0x0F, the temperature's
    row does not list it)."""
    values = [0] * 49
    values[13:21] = reply.proximity
    values[21:29] = reply.ambient
    values[30:34] = reply.microphones
    values[34:36] = reply.steps
    values[41] = reply.selector
    return tuple(values)
