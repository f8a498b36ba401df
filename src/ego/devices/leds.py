"""The LEDs: led0..led7 ring, led8 body, led9 front (wire command L; the e-puck2's RGB
ones -0x0A, ego.devices.rgb_leds)."""

from __future__ import annotations

import enum

from ego.devices.base import Actuator
from ego.devices.rgb_leds import MAX_COLOUR, colour_request
from ego.devices.table import TABLE
from ego.errors import UnsupportedDeviceError
from ego.seam.batch import Request
from ego.seam.profile import Command, Profile
from ego.seam.validate import check_int

__all__ = ["LedValue", "Leds"]


class LedValue(enum.IntEnum):
    OFF = 0
    ON = 1
    TOGGLE = 2


@TABLE.declare("leds", webots_rank=1)
class Leds(Actuator):
    """Ten LEDs set to 0 (off), 1 (on) or 2 (toggle); a command goes out only on change.

    The stock Overo firmware ignores ``L 8`` and ``L 9`` (body, front): setting them there
    raises UnsupportedDeviceError instead of doing nothing.

    Where the profile has RGB LEDs (the e-puck2's led1, led3, led5, led7), their value is
    a colour ``0xRRGGBB`` as Webots' ``LED.set`` takes it (0 is off), and the four go
    together as one ``-0x0A``.

    >>> robot.leds.set("led0", 1)                        # doctest: +SKIP
    >>> robot.leds.set(8, LedValue.TOGGLE)
    >>> robot.leds.set("led1", 0xFF8000)                 # an e-puck2's RGB LED: orange
    """

    family = "LEDs"

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
        if index in self.profile.rgb_leds:
            self._set_colour(index, value)
            return
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

    def _set_colour(self, index: int, colour: int) -> None:
        colour = check_int(f"colour for {self.names[index]}", colour, 0, MAX_COLOUR)
        if colour != self._state[index]:
            self._state[index] = colour
            self.queue("rgb", self._colours())

    def _colours(self) -> Request:
        return colour_request([self._state[i] for i in self.profile.rgb_leds])

    @property
    def rgb(self) -> tuple[int, ...]:
        """The LEDs that take a colour ``0xRRGGBB`` on this firmware (none on an e-puck1)."""
        return self.profile.rgb_leds

    def get(self, led: int | str) -> int:
        """The state ego last sent: 0 off, 1 on (an RGB LED's colour, ``0xRRGGBB``)."""
        return self._state[self.index(led)]

    @property
    def values(self) -> tuple[int, ...]:
        return tuple(self._state)

    def all_off(self) -> list[Request]:
        """Requests that switch every LED this firmware drives off, whatever ego believes."""
        for i in (*self.profile.leds, *self.profile.rgb_leds):
            self._state[i] = 0
        off = [Request(Command.SET_LED, (i, 0)) for i in self.profile.leds]
        return off + ([self._colours()] if self.profile.rgb_leds else [])

    def switched_off(self, leds: tuple[int, ...]) -> None:
        """The dsPIC switched these LEDs off itself (ASCII ``S``); ego's view follows."""
        for i in leds:
            self._state[i] = 0
            self._pending.pop(i, None)
        if self.profile.rgb_leds and set(self.profile.rgb_leds) <= set(leds):
            self._pending.pop("rgb", None)

    def reset(self) -> None:
        """A restarted dsPIC has its LEDs off: switch on again those that were on."""
        for i in self.profile.leds:
            if self._state[i]:
                self.queue(i, Request(Command.SET_LED, (i, 1)))
        if any(self._state[i] for i in self.profile.rgb_leds):
            self.queue("rgb", self._colours())
