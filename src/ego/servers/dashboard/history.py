"""The last minute of a dashboard's samples, kept for a page that opens late.

The server keeps a sample every :data:`KEEP_EVERY_S` (whether or not a page watches),
drops those more than :data:`HISTORY_S` of run time older than the newest, and sends
them to each page as it connects (one ``{"type": "history", "samples": [...]}``
message), so that its plots and its path start a minute back, not empty. A run whose
time goes back (a replay seeking backwards, a new run) starts the history afresh.
"""

from __future__ import annotations

import json
import threading
import time
from collections import deque
from collections.abc import Callable
from typing import Any

__all__ = ["HISTORY_S", "KEEP_EVERY_S", "History"]

#: How much run time the history spans (s).
HISTORY_S = 60.0
#: How often a sample is kept (s of wall time): 10 a second, 600 a minute.
KEEP_EVERY_S = 0.1


class History:
    """A minute of samples (dicts with a ``t`` in seconds); thread-safe."""

    def __init__(
        self,
        span_s: float = HISTORY_S,
        every_s: float = KEEP_EVERY_S,
        clock: Callable[[], float] = time.monotonic,
    ) -> None:
        self.span_s = span_s
        self.every_s = every_s
        self._clock = clock
        self._samples: deque[dict[str, Any]] = deque()
        self._next = -float("inf")  # when the next sample is due (wall clock)
        self._lock = threading.Lock()

    def due(self) -> bool:
        """Whether a sample given now would be kept (so that one is only made then)."""
        return self._clock() >= self._next

    def add(self, sample: dict[str, Any]) -> None:
        """Keep ``sample`` if one is due; forget what is over a minute older than it."""
        now = self._clock()
        with self._lock:
            if now < self._next:
                return
            t = float(sample["t"])
            if self._samples and t < float(self._samples[-1]["t"]):
                self._samples.clear()  # the run's time went back: a seek, a new run
            # On the beat (a 25 Hz feed gives 10 a second, not every third sample), unless
            # samples stopped coming for a while.
            late = now - self._next >= self.every_s
            self._next = (now if late else self._next) + self.every_s
            self._samples.append(sample)
            while t - float(self._samples[0]["t"]) > self.span_s:
                self._samples.popleft()

    def samples(self) -> list[dict[str, Any]]:
        """The kept samples, oldest first."""
        with self._lock:
            return list(self._samples)

    def message(self) -> str:
        """The JSON message a connecting page gets."""
        return json.dumps({"type": "history", "samples": self.samples()})

    def __len__(self) -> int:
        return len(self._samples)
