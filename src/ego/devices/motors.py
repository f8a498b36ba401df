"""The two stepper motors: speeds in steps/s (wire command D), commanded speeds back (E)."""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import ClassVar

from ego.devices.base import Sensor, check_int
from ego.serial.protocol import MAX_SPEED_STEPS, STEPS_PER_TURN, Command, Profile, Request

__all__ = ["MAX_SPEED_RAD_S", "Motors", "rad_s_to_steps", "steps_to_rad_s"]

#: 1000 steps/s is one wheel turn a second.
MAX_SPEED_RAD_S = 2 * math.pi * MAX_SPEED_STEPS / STEPS_PER_TURN


def rad_s_to_steps(speed_rad_s: float) -> float:
    return speed_rad_s * STEPS_PER_TURN / (2 * math.pi)


def steps_to_rad_s(speed_steps: float) -> float:
    return speed_steps * 2 * math.pi / STEPS_PER_TURN


class Motors(Sensor):
    """Wheel speeds in steps/s within +-1000 (one turn a second); refused beyond, not clamped.

    A ``D`` command goes out only when the speeds changed, with an ``E`` behind it that
    confirms the dsPIC holds them. Enabled as a sensor, the family also reads back the
    speeds the firmware holds at every period (``E``: commanded, not measured).

    >>> robot.motors.set_speed(300, -300)                # doctest: +SKIP
    """

    family = "motors"
    names: ClassVar[tuple[str, ...]] = ("left wheel motor", "right wheel motor")
    command = Command.GET_SPEED

    def __init__(self, profile: Profile) -> None:
        super().__init__(profile)
        self._speed = (0, 0)
        self._pending: Request | None = None
        self._firmware_speed = (0, 0)

    def set_speed(self, left: float, right: float) -> None:
        """Both wheel speeds in steps/s, each within +-1000."""
        speeds = tuple(
            check_int(
                f"{side} speed", v, -MAX_SPEED_STEPS, MAX_SPEED_STEPS, " steps/s", rounding=True
            )
            for side, v in (("left", left), ("right", right))
        )
        if speeds != self._speed:
            self._speed = (speeds[0], speeds[1])
            self._pending = Request(Command.SET_SPEED, self._speed)

    @property
    def speed(self) -> tuple[int, int]:
        """The speeds ego last asked for, steps/s."""
        return self._speed

    def stop_request(self) -> Request:
        """A request that stops both wheels, whatever ego believes."""
        self._speed = (0, 0)
        self._pending = None
        return Request(Command.SET_SPEED, (0, 0))

    def requests(self, now_ms: int) -> list[Request]:
        # A D always travels with an E behind it, sampled or not: a D whose bytes the
        # dsPIC misread (no length check can see a flipped speed byte) is then caught by
        # check() and sent again, instead of driving the wheels at a wrong speed.
        if self._pending is not None:
            return [self._pending, Request(Command.GET_SPEED)]
        return super().requests(now_ms)

    def check(self, request: Request, values: Sequence[float], now_s: float) -> str | None:
        """E echoes the speeds the dsPIC holds: they must be the ones ego asked for.

        A mismatch is a corrupted reply, or a D the dsPIC misread or never got: either
        way, send the speeds again.
        """
        if request.command is not Command.GET_SPEED:
            return None
        held = (int(values[0]), int(values[1]))
        if held == self._speed:
            return None
        self._pending = Request(Command.SET_SPEED, self._speed)
        return f"the dsPIC holds speeds {held}, ego asked for {self._speed}"

    def decode(self, request: Request, values: Sequence[float], now_ms: int) -> None:
        if request.command is Command.GET_SPEED:
            super().decode(request, values, now_ms)

    def committed(self, now_ms: int) -> None:
        self._pending = None

    def take(self, values: Sequence[float]) -> None:
        self._firmware_speed = (int(values[0]), int(values[1]))

    @property
    def values(self) -> tuple[int, int]:
        """The speeds the firmware reports holding (E), from the last sample."""
        self.require_values()
        return self._firmware_speed

    def restarted(self) -> None:
        """A restarted dsPIC stands still: ask for the current speeds again."""
        super().restarted()
        if self._speed != (0, 0):
            self._pending = Request(Command.SET_SPEED, self._speed)
