"""The LEDs: led0..led7 ring, led8 body, led9 front (wire command L)."""

from __future__ import annotations

import enum

from ego.devices.base import Actuator, check_int
from ego.errors import UnsupportedDeviceError
from ego.serial.protocol import Command, Profile, Request

__all__ = ["LedValue", "Leds"]


class LedValue(enum.IntEnum):
    OFF = 0
    ON = 1
    TOGGLE = 2


class Leds(Actuator):
    """Ten LEDs set to 0 (off), 1 (on) or 2 (toggle); a command goes out only on change.

    The stock Overo firmware ignores ``L 8`` and ``L 9`` (body, front): setting them there
    raises UnsupportedDeviceError instead of doing nothing.

    >>> robot.leds.set("led0", 1)                        # doctest: +SKIP
    >>> robot.leds.set(8, LedValue.TOGGLE)
    """

    family = "LEDs"
    table_family = "leds"

    def __init__(self, profile: Profile) -> None:
        super().__init__(profile)
        self._state = [0] * len(self.names)

    def index(self, led: int | str) -> int:
        if isinstance(led, str):
            return self.names.index(self.check_name(led))
        index = check_int("LED number", led, 0, len(self.names) - 1)
        return index

    def set(self, led: int | str, value: int) -> None:
        """Switch ``led`` (a name or 0..9) off (0), on (1) or toggle it (2)."""
        index = self.index(led)
        action = LedValue(check_int(f"value for {self.names[index]}", value, 0, 2))
        if index not in self.profile.leds:
            driven = ", ".join(self.names[i] for i in self.profile.leds)
            raise UnsupportedDeviceError(
                f"the {self.profile.firmware} firmware ({self.profile.description}) ignores "
                f"{self.names[index]}; it drives {driven}"
            )
        new = 1 - self._state[index] if action is LedValue.TOGGLE else int(action)
        if new != self._state[index]:
            self._state[index] = new
            self.queue(index, Request(Command.SET_LED, (index, new)))

    def get(self, led: int | str) -> int:
        """The state ego last sent: 0 off, 1 on."""
        return self._state[self.index(led)]

    @property
    def values(self) -> tuple[int, ...]:
        return tuple(self._state)

    def all_off(self) -> list[Request]:
        """Requests that switch every LED this firmware drives off, whatever ego believes."""
        for i in self.profile.leds:
            self._state[i] = 0
        return [Request(Command.SET_LED, (i, 0)) for i in self.profile.leds]

    def switched_off(self, leds: tuple[int, ...]) -> None:
        """The dsPIC switched these LEDs off itself (ASCII ``S``); ego's view follows."""
        for i in leds:
            self._state[i] = 0
            self._pending.pop(i, None)

    def reset(self) -> None:
        """A restarted dsPIC has its LEDs off: switch on again those that were on."""
        for i in self.profile.leds:
            if self._state[i]:
                self.queue(i, Request(Command.SET_LED, (i, 1)))
