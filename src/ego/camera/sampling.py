"""The camera's sampling schedule: a period, and absolute deadlines a capture is due at."""

from __future__ import annotations

from ego.errors import OutOfRangeError
from ego.seam.validate import MAX_PERIOD_MS, check_int

__all__ = ["SamplingSchedule"]


class SamplingSchedule:
    """When a camera's frames are due: every ``period_ms`` from the first update, on
    absolute deadlines (no drift); after a stall longer than a period, the next one is a
    period from now rather than a burst. Pure: the Camera captures when told it is due."""

    def __init__(self) -> None:
        #: The sampling period in ms, or None when disabled.
        self.period_ms: int | None = None
        self._next_due_ms: float | None = None

    @staticmethod
    def checked(period_ms: int) -> int:
        """``period_ms`` if it is a valid period (1..MAX_PERIOD_MS), else OutOfRangeError."""
        period_ms = check_int("period_ms", period_ms, integral=True)
        if not 0 < period_ms <= MAX_PERIOD_MS:
            # the same bound as every other sensor's: anything longer is a unit mistake
            raise OutOfRangeError(
                f"sampling period {period_ms} ms must be positive, at most {MAX_PERIOD_MS} ms"
            )
        return period_ms

    def start(self, period_ms: int) -> None:
        """Sample every ``period_ms`` (checked already), the first frame at the next update."""
        self.period_ms = period_ms
        self._next_due_ms = None

    def stop(self) -> None:
        self.period_ms = None
        self._next_due_ms = None

    def is_due(self, now_ms: float) -> bool:
        """Whether a frame is due at ``now_ms``."""
        if self.period_ms is None:
            return False
        return self._next_due_ms is None or now_ms >= self._next_due_ms

    def taken(self, now_ms: float) -> None:
        """A frame due at ``now_ms`` was captured: set the next deadline."""
        assert self.period_ms is not None, "taken() while disabled"
        due = now_ms if self._next_due_ms is None else self._next_due_ms
        due += self.period_ms
        self._next_due_ms = due if due > now_ms else now_ms + self.period_ms
