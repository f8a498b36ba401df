"""The two stepper motors: speeds in steps/s (wire command D), commanded speeds back (E)."""

from __future__ import annotations

import math
from collections.abc import Sequence

from ego.devices.base import FINE, ActingFamily, Device, Sensor, Verdict
from ego.devices.table import TABLE
from ego.seam.batch import Request
from ego.seam.profile import Command, Profile
from ego.seam.validate import check_int
from ego.serial.profiles import MAX_SPEED_STEPS, STEPS_PER_TURN

__all__ = ["MAX_SPEED_RAD_S", "Motors", "rad_s_to_steps", "real_speed_steps", "steps_to_rad_s"]

#: The motors' step timer, in ticks a second (docs/protocol.md, quirk "D").
STEP_TIMER_HZ = 10000

#: 1000 steps/s is one wheel turn a second.
MAX_SPEED_RAD_S = 2 * math.pi * MAX_SPEED_STEPS / STEPS_PER_TURN


def rad_s_to_steps(speed_rad_s: float) -> float:
    return speed_rad_s * STEPS_PER_TURN / (2 * math.pi)


def steps_to_rad_s(speed_steps: float) -> float:
    return speed_steps * 2 * math.pi / STEPS_PER_TURN


def real_speed_steps(speed_steps: int) -> float:
    """The speed the wheel really turns at when asked ``speed_steps`` (clamped to +-1000).

    The dsPIC steps every ``floor(10000 / |v|)`` ticks of its 10 kHz timer.
    """
    v = max(-MAX_SPEED_STEPS, min(MAX_SPEED_STEPS, int(speed_steps)))
    if v == 0:
        return 0.0
    return math.copysign(STEP_TIMER_HZ / (STEP_TIMER_HZ // abs(v)), v)


@TABLE.part_of("motors")
class WheelSpeeds(Device):
    """The actuator side of the motors: ``D`` when the speeds changed, confirmed by an ``E``.

    A ``D`` always travels with an ``E`` behind it, sampled or not: a ``D`` whose bytes
    the dsPIC misread (no length check can see a flipped speed byte) is then caught by
    the ``E`` that must echo the speeds, and sent again, instead of driving the wheels at
    a wrong speed.
    """

    family = "motors"

    def __init__(self, profile: Profile) -> None:
        super().__init__(profile)
        self.speed = (0, 0)
        self.pending: Request | None = None
        #: The speeds the batch in flight asks for: the controller may set others while
        #: it runs (Webots' stepBegin..stepEnd), which go in the next batch.
        self.asked = (0, 0)
        #: The read-back the confirming E also refreshes.
        self.echo: Sensor | None = None

    def set(self, left: int, right: int) -> None:
        if (left, right) != self.speed:
            self.speed = (left, right)
            self.pending = Request(Command.SET_SPEED, self.speed)

    def plan(self, now_ms: int) -> list[Request]:
        if self.pending is None:
            return []
        left, right = self.pending.arguments
        self.asked = (left, right)
        return [self.pending, Request(Command.GET_SPEED)]

    def validate(self, request: Request, values: Sequence[float], now_s: float) -> Verdict:
        """E echoes the speeds the dsPIC holds: they must be the ones ego asked for.

        A mismatch is a corrupted reply, or a D the dsPIC misread or never got: either
        way, the speeds go again.
        """
        if request.command is not Command.GET_SPEED:
            return FINE
        held = (int(values[0]), int(values[1]))
        if held == self.asked:
            return FINE
        return Verdict(
            f"the dsPIC holds speeds {held}, ego asked for {self.asked}",
            correction=Request(Command.SET_SPEED, self.speed),
        )

    def refused(self, verdict: Verdict, now_s: float) -> None:
        if verdict.correction is not None:
            self.pending = verdict.correction

    def apply(self, request: Request, values: Sequence[float], now_ms: int, now_s: float) -> None:
        if request == self.pending:
            self.pending = None
        elif request.command is Command.GET_SPEED and self.echo is not None:
            self.echo.apply(request, values, now_ms, now_s)

    def reset(self) -> None:
        """A restarted dsPIC stands still: ask for the current speeds again."""
        if self.speed != (0, 0):
            self.pending = Request(Command.SET_SPEED, self.speed)


@TABLE.part_of("motors")
class SpeedReadback(Sensor):
    """The sensor side of the motors: the speeds the firmware holds (``E``: commanded, not
    measured), sampled at its period when enabled."""

    family = "motors"
    command = Command.GET_SPEED

    def __init__(self, profile: Profile, wheels: WheelSpeeds) -> None:
        super().__init__(profile)
        self._wheels = wheels
        self.held = (0, 0)

    def plan(self, now_ms: int) -> list[Request]:
        # A D's confirming E is read anyway: no second E in the same batch.
        return [] if self._wheels.pending is not None else super().plan(now_ms)

    def take(self, values: Sequence[float]) -> None:
        self.held = (int(values[0]), int(values[1]))


@TABLE.declare("motors", webots_rank=0)
class Motors(ActingFamily):
    """Wheel speeds in steps/s within +-1000 (one turn a second); refused beyond, not clamped.

    A ``D`` command goes out only when the speeds changed, with an ``E`` behind it that
    confirms the dsPIC holds them. Enabled as a sensor, the family also reads back the
    speeds the firmware holds at every period (``E``: commanded, not measured).

    The wheels do not turn at exactly the speed asked (docs/protocol.md, quirk "D"): the
    dsPIC steps a motor every ``floor(10000 / |v|)`` ticks of a 10 kHz timer, so the
    real speed is ``10000 / floor(10000 / |v|)`` steps/s: 950 runs at 1000, 600 at 625,
    300 at 303. :func:`real_speed_steps` gives it; odometry should use it. An RC5 TV
    remote pointed at the robot also sets the speeds, even in Overo mode; the ``E`` check
    then sees speeds ego did not ask for and sends ego's again.

    >>> robot.motors.set_speed(300, -300)                # doctest: +SKIP
    """

    family = "motors"

    def __init__(self, profile: Profile) -> None:
        self.wheels = WheelSpeeds(profile)
        self.readback = SpeedReadback(profile, self.wheels)
        self.wheels.echo = self.readback
        super().__init__(profile, self.wheels, self.readback)

    def set_speed(self, left: float, right: float) -> None:
        """Both wheel speeds in steps/s, each within +-1000 (+-1100 on an e-puck2, whose
        firmware clamps there: MAIN:src/motors.h:7)."""
        limit = self.profile.max_speed_steps  # 1000 on an e-puck1, 1100 on an e-puck2
        speeds = [
            check_int(f"{side} speed", v, -limit, limit, " steps/s", rounding=True)
            for side, v in (("left", left), ("right", right))
        ]
        self.wheels.set(speeds[0], speeds[1])

    @property
    def speed(self) -> tuple[int, int]:
        """The speeds ego last asked for, steps/s."""
        return self.wheels.speed

    def stop_request(self) -> Request:
        """A request that stops both wheels, whatever ego believes."""
        self.wheels.speed, self.wheels.pending = (0, 0), None
        return Request(Command.SET_SPEED, (0, 0))

    def stopped_by_firmware(self, resend: bool) -> None:
        """The dsPIC stopped the wheels itself (ASCII ``S``); ego's view follows.

        ``resend``: its ``E`` still echoes the old speeds (the stock firmware), so a
        ``D 0 0`` goes out with the next batch to make the echo true again.
        """
        self.wheels.speed = (0, 0)
        self.wheels.pending = Request(Command.SET_SPEED, (0, 0)) if resend else None

    @property
    def values(self) -> tuple[int, int]:
        """The speeds the firmware reports holding (E), from the last sample."""
        self.readback.require_values()
        return self.readback.held
