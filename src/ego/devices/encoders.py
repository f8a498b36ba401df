"""The wheels' step counters, left and right (wire commands Q to read, P to set)."""

from __future__ import annotations

import math
from collections.abc import Sequence

from ego.devices.base import FINE, ActingFamily, Device, Sensor, Verdict
from ego.devices.table import STEP_RAD, TABLE, Series
from ego.seam.batch import Request
from ego.seam.profile import Command, Profile
from ego.seam.validate import check_int
from ego.serial.profiles import MAX_SPEED_STEPS, STEPS_PER_TURN

__all__ = ["Encoders", "wrap_int16"]

_INT16 = 1 << 16
#: Steps a counter may move beyond full speed x elapsed time (scheduling jitter).
JUMP_SLACK_STEPS = 50


def wrap_int16(value: int) -> int:
    """``value`` as the dsPIC's int16 counter holds it."""
    return ((value + 0x8000) % _INT16) - 0x8000


def _jump(raw: Sequence[int], last: Sequence[int], elapsed_s: float) -> str | None:
    """Why counters cannot have gone from ``last`` to ``raw`` in ``elapsed_s``, or None."""
    allowed = MAX_SPEED_STEPS * elapsed_s * 1.5 + JUMP_SLACK_STEPS
    for side, now, before in zip(("left", "right"), raw, last, strict=True):
        moved = abs(wrap_int16(now - before))
        if moved > allowed:
            return f"{side} step counter jumped {moved} steps, more than {allowed:.0f} possible"
    return None


@TABLE.part_of("encoders")
class CounterReset(Device):
    """The actuator side of the encoders: ``P`` overwrites the dsPIC's step counters."""

    family = "encoders"

    def __init__(self, profile: Profile) -> None:
        super().__init__(profile)
        self.pending: Request | None = None

    def plan(self, now_ms: int) -> list[Request]:
        return [self.pending] if self.pending is not None else []

    def apply(self, request: Request, values: Sequence[float], now_ms: int, now_s: float) -> None:
        if request == self.pending:
            self.pending = None


@TABLE.part_of("encoders")
class StepCounters(Sensor):
    """The sensor side of the encoders: ``Q``, kept as totals beyond the firmware's int16."""

    family = "encoders"
    command = Command.GET_STEPS

    def __init__(self, profile: Profile, reset: CounterReset) -> None:
        super().__init__(profile)
        self._reset = reset
        self.total = [0, 0]
        self.last_raw: list[int] | None = None
        self._fetched_s: float | None = None
        #: A reading the guard refused, and when: the next one tells a garbled reply
        #: (which does not repeat) from counters really overwritten on the dsPIC.
        self._suspect: tuple[tuple[int, int], float] | None = None

    def validate(self, request: Request, values: Sequence[float], now_s: float) -> Verdict:
        """A counter that moved further than a wheel at full speed could is corrupted.

        A garbled reply does not repeat: asked again, the dsPIC answers the true counts.
        If it answers the same jump twice, its counters really were overwritten (a
        command byte misread as ``P`` takes the next four bytes for counts): the verdict
        sets them back to the last good reading, losing at most the steps turned since
        then, and reads again, instead of refusing every reading until the jump looks
        plausible.
        """
        if self.last_raw is None or self._reset.pending is not None or self._fetched_s is None:
            return FINE  # nothing to compare with, or P overwrote the counters just now
        raw = (int(values[0]), int(values[1]))
        jump = _jump(raw, self.last_raw, now_s - self._fetched_s)
        if jump is None:
            return FINE
        suspect = self._suspect
        if suspect is None or _jump(raw, suspect[0], now_s - suspect[1]) is not None:
            return Verdict(jump, note=(raw, now_s))
        return Verdict(
            f"{jump}, twice: the dsPIC's counters were overwritten (a misread command?); "
            f"setting them back to {tuple(self.last_raw)}",
            correction=_set_back(self.last_raw),
        )

    def refused(self, verdict: Verdict, now_s: float) -> None:
        if verdict.correction is not None:
            self._suspect = None
            self._reset.pending = verdict.correction
        else:
            self._suspect = verdict.note  # type: ignore[assignment]

    def apply(self, request: Request, values: Sequence[float], now_ms: int, now_s: float) -> None:
        super().apply(request, values, now_ms, now_s)
        self._fetched_s = now_s
        self._suspect = None

    def take(self, values: Sequence[float]) -> None:
        raw = [int(v) for v in values]
        if self.last_raw is not None:
            for i in (0, 1):
                self.total[i] += wrap_int16(raw[i] - self.last_raw[i])
        else:
            self.total = raw
        self.last_raw = raw

    def reset(self) -> None:
        """A restarted dsPIC counts from 0 again: give it our totals back."""
        super().reset()
        self._suspect = None
        if self.last_raw is not None:
            self._reset.pending = _set_back(self.last_raw)


def _set_back(raw: Sequence[int]) -> Request:
    """P with the counters' last good reading: what the dsPIC must hold again."""
    return Request(Command.SET_STEPS, (raw[0], raw[1]))


@TABLE.declare(
    "encoders",
    webots_rank=2,
    series=Series("encoders", "steps", ("left", "right"), ("rad", STEP_RAD)),
)
class Encoders(ActingFamily):
    """Steps counted by each stepper motor since start or since set, unwrapped.

    The dsPIC's counters are int16 and wrap at +-32768 (about 4 m of travel); ego keeps
    the running total, so a long drive never jumps back. 1000 steps are one wheel turn.

    >>> robot.encoders.enable(64)                        # doctest: +SKIP
    >>> robot.step(64); left, right = robot.encoders.values
    """

    family = "encoders"

    def __init__(self, profile: Profile) -> None:
        self.reset_part = CounterReset(profile)
        self.counters = StepCounters(profile, self.reset_part)
        super().__init__(profile, self.reset_part, self.counters)

    def set(self, left: int, right: int) -> None:
        """Overwrite both counters (steps); the firmware stores them as int16."""
        values = [
            check_int(f"{side} encoder value", v, -(2**31), 2**31 - 1, " steps")
            for side, v in (("left", left), ("right", right))
        ]
        self.counters.total = values
        self.counters.last_raw = [wrap_int16(v) for v in values]
        self.reset_part.pending = _set_back(self.counters.last_raw)

    @property
    def values(self) -> tuple[int, int]:
        """Left and right totals in steps."""
        self.counters.require_values()
        return (self.counters.total[0], self.counters.total[1])

    def readings(self) -> list[float] | None:
        return [float(v) for v in self.values] if self.has_values else None

    @property
    def radians(self) -> tuple[float, float]:
        """Left and right wheel angles in radians (Webots' PositionSensor unit)."""
        left, right = self.values
        k = 2 * math.pi / STEPS_PER_TURN
        return (left * k, right * k)
