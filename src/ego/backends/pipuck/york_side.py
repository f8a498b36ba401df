"""An e-puck1's side of a Pi-puck (York's firmware): ego's requests as register writes,
and the registers a step's getters need read back, one SMBus word each.

No checksum protects these transfers; a failed transfer is retried (:data:`ATTEMPTS` in
all), then raised as a typed error; implausible values are the families' to refuse.
The IR sensors measure only once register 6's bit 0 is set (``main.c:40, 83-94``): ego
sets it when proximity or ambient light is first asked. The step counters (registers 4
and 5) are read-only, so setting them (``P``, which ego's encoders send to set counters
back after a garbled reading) is an offset ego adds to what the firmware counts.
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from dataclasses import replace
from typing import Final, TypeVar

from ego.backends.pipuck import york
from ego.backends.pipuck.bus import RobotBus, i2c_failure
from ego.errors import LinkTimeoutError, UnsupportedDeviceError
from ego.seam.batch import Request
from ego.seam.profile import Command, Profile
from ego.serial.pipuck import YORK_PROFILE

__all__ = ["ATTEMPTS", "YorkSide"]

log = logging.getLogger(__name__)

ATTEMPTS: Final = 3
_T = TypeVar("_T")


class YorkSide:
    """The e-puck1 at 0x1F on ``bus``, York's register map."""

    profile: Profile = YORK_PROFILE
    answers: frozenset[Command] = frozenset({Command.PROXIMITY, Command.LIGHT, Command.GET_STEPS,
                                Command.GET_SPEED})  # fmt: skip

    def __init__(self, bus: RobotBus, name: str) -> None:
        self.bus = bus
        self.name = name
        self.state = york.YorkState()
        self._sent: york.YorkState | None = None
        self._values: dict[Command, tuple[int, ...]] = {}
        self._offset = (0, 0)  # what SET_STEPS set, over the firmware's own counts
        self.retries = 0

    def fold(self, request: Request) -> None:
        command, args = request.command, request.arguments
        if command is Command.SET_SPEED:
            self.state = self.state.with_speeds(args[0], args[1])
        elif command is Command.SET_LED:
            self.state = self.state.with_led(args[0], args[1])
        elif command is Command.SET_STEPS:
            # Registers 4 and 5 are read-only (main.c:80-81 rewrites them every loop): the
            # counters are set here, as an offset to what the firmware counts [ego's way].
            raw = self._words((york.STEPS_LEFT, york.STEPS_RIGHT))
            self._offset = (york.signed((args[0] - raw[0]) & 0xFFFF),
                            york.signed((args[1] - raw[1]) & 0xFFFF))  # fmt: skip
        else:
            raise UnsupportedDeviceError(
                f"{self.name}: York's register map has no {command.name.lower()}"
            )

    def _retried(self, what: str, call: Callable[[], _T]) -> _T:
        for attempt in range(ATTEMPTS):
            try:
                return call()
            except OSError as exc:
                error = LinkTimeoutError(i2c_failure(exc, f"{self.name}: {what}"))
            self.retries += 1
            log.warning("%s (attempt %d of %d)", error, attempt + 1, ATTEMPTS)
        raise error

    def _write(self) -> None:
        for register, value, word in york.writes(self.state, self._sent):
            write = self.bus.write_word if word else self.bus.write_byte
            self._retried(f"writing register {register}",
                          lambda: write(york.ADDRESS, register, value))  # noqa: B023
        self._sent = self.state

    def _words(self, registers: tuple[int, ...]) -> tuple[int, ...]:
        return tuple(
            self._retried(f"reading register {r}", lambda: self.bus.read_word(york.ADDRESS, r))  # noqa: B023
            for r in registers
        )

    def sync(self, getters: tuple[Command, ...]) -> None:
        """Write what changed, then read what ``getters`` need."""
        if {Command.PROXIMITY, Command.LIGHT} & set(getters) and not self.state.ir_on:
            self.state = replace(self.state, ir_on=True)
        self._write()
        values: dict[Command, tuple[int, ...]] = {}
        for command in dict.fromkeys(getters):
            if command is Command.PROXIMITY:
                values[command] = tuple(york.signed(w) for w in self._words(york.PROXIMITY))
            elif command is Command.LIGHT:
                values[command] = tuple(york.signed(w) for w in self._words(york.AMBIENT))
            elif command is Command.GET_STEPS:
                words = self._words((york.STEPS_LEFT, york.STEPS_RIGHT))
                values[command] = tuple(  # u16: as int16, as the serial Q answers
                    york.signed((w + o) & 0xFFFF) for w, o in zip(words, self._offset, strict=True)
                )
            elif command is Command.GET_SPEED:
                words = self._words((york.SPEED_LEFT, york.SPEED_RIGHT))
                values[command] = tuple(york.signed(w) for w in words)
        self._values = values

    def answer(self, command: Command) -> tuple[int, ...]:
        return self._values[command]

    def stop_message(self) -> None:
        """Speeds 0 and every LED off, every register written whatever ego believes."""
        self.state = replace(york.YorkState(), ir_on=self.state.ir_on)
        self._sent = None
        self._write()
