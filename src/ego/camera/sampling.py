"""The camera's sampling: enabled at a period, captured by the step when it is due."""

from __future__ import annotations

from typing import TYPE_CHECKING

from ego.errors import OutOfRangeError
from ego.seam.validate import MAX_PERIOD_MS, check_int

if TYPE_CHECKING:
    from ego.camera.source import GrantedFormat

__all__ = ["CameraSampling"]


class CameraSampling:
    """The part of :class:`~ego.camera.Camera` the step clock drives (the scheduler's
    interface): a period, absolute deadlines, a capture when one is due."""

    _granted: GrantedFormat | None
    _period_ms: int | None
    _next_due_ms: float | None
    _closed: bool

    def _open_source(self) -> None:
        raise NotImplementedError

    def _check_open(self) -> None:
        raise NotImplementedError

    def capture(self) -> object:
        """Read one frame from the source now (the Camera's)."""
        raise NotImplementedError

    def enable(self, period_ms: int) -> None:
        """Capture a frame every ``period_ms`` ms (> 0); opens the source on first use."""
        period_ms = check_int("period_ms", period_ms, integral=True)
        if not 0 < period_ms <= MAX_PERIOD_MS:
            # the same bound as every other sensor's: anything longer is a unit mistake
            raise OutOfRangeError(
                f"sampling period {period_ms} ms must be positive, at most {MAX_PERIOD_MS} ms"
            )
        if self._granted is None:
            self._open_source()
        self._check_open()
        self._period_ms = period_ms
        self._next_due_ms = None  # due at the next update

    def disable(self) -> None:
        """Stop sampling (the source stays open: enabling again is quick)."""
        self._period_ms = None
        self._next_due_ms = None

    @property
    def sampling_period(self) -> int | None:
        """The sampling period in ms, or ``None`` when disabled."""
        return self._period_ms

    def is_due(self, now_ms: float) -> bool:
        """Whether ``update(now_ms)`` would capture a frame."""
        if self._period_ms is None or self._closed:
            return False
        return self._next_due_ms is None or now_ms >= self._next_due_ms

    def update(self, now_ms: float) -> bool:
        """Capture and convert a frame if one is due at ``now_ms``; True if it did.

        Deadlines are absolute (``period_ms`` apart, no drift); after a stall longer
        than a period the next one is a period from now rather than a burst.
        """
        if not self.is_due(now_ms):
            return False
        assert self._period_ms is not None
        self.capture()
        due = now_ms if self._next_due_ms is None else self._next_due_ms
        due += self._period_ms
        self._next_due_ms = due if due > now_ms else now_ms + self._period_ms
        return True
