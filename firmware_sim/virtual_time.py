"""Virtual time: a clock that only the controller's steps move, for runs faster than real
time (as Webots' fast mode), with the same world, sensor model and serial batches."""

from __future__ import annotations

import threading

__all__ = ["VirtualClock"]


class VirtualClock:
    """Seconds that pass only when :meth:`advance` says so; call it to read the time."""

    def __init__(self, start_s: float = 0.0) -> None:
        self._now_s = start_s
        self._lock = threading.Lock()

    def __call__(self) -> float:
        with self._lock:
            return self._now_s

    def advance(self, seconds: float) -> None:
        """Let ``seconds`` (>= 0, finite) of world time pass."""
        if not 0.0 <= seconds < float("inf"):
            raise ValueError(f"virtual time moves forward by a finite amount, not {seconds!r}")
        with self._lock:
            self._now_s += seconds
