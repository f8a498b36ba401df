"""What a controller is told about late steps: the first at once, the rest summarised.

A step loop whose work outlasts its step (``step(1)`` with 2 ms of work) overruns every
step; a warning each would flood the terminal with thousands of identical lines. This
sans-I/O report says the first overrun at once, then one summary line per period (how
many, how late on average and at worst), and a last one when the clock closes.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["OverrunReport"]

#: Seconds between two summary lines while overruns go on.
SUMMARY_PERIOD_S = 10.0


@dataclass
class OverrunReport:
    """Fed each overrun with the time it happened; returns the line to log, if any."""

    period_s: float = SUMMARY_PERIOD_S
    total: int = 0
    _window_start_s: float | None = None
    _count: int = 0
    _late_sum_s: float = 0.0
    _worst_s: float = 0.0

    def note(self, now_s: float, step_ms: float, late_s: float) -> str | None:
        """One overrun of a ``step_ms`` step, ``late_s`` late, at ``now_s`` (a clock's s)."""
        self.total += 1
        if self.total == 1:
            self._window_start_s = now_s
            return (
                f"step of {step_ms:g} ms overran by {late_s * 1e3:.2f} ms: the controller's "
                f"work takes longer than its step (later overruns are summarised every "
                f"{self.period_s:g} s)"
            )
        self._count += 1
        self._late_sum_s += late_s
        self._worst_s = max(self._worst_s, late_s)
        assert self._window_start_s is not None
        if now_s - self._window_start_s >= self.period_s:
            return self._summary(now_s)
        return None

    def flush(self, now_s: float) -> str | None:
        """The summary of the overruns not yet told (at close), if any."""
        return self._summary(now_s) if self._count else None

    def _summary(self, now_s: float) -> str:
        assert self._window_start_s is not None
        line = (
            f"{self._count} more overruns in {now_s - self._window_start_s:.1f} s, late by "
            f"{self._late_sum_s / self._count * 1e3:.2f} ms on average, "
            f"{self._worst_s * 1e3:.2f} ms at worst ({self.total} in all)"
        )
        self._window_start_s = now_s
        self._count = 0
        self._late_sum_s = self._worst_s = 0.0
        return line
