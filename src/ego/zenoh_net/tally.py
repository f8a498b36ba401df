"""Counting what a Zenoh node or radio refused or dropped, and saying so without a flood of logs.

A peer may send thousands of bad queries or packets a second: each is counted, by
reason, but only the first of a burst is logged at once; later ones are summed into
one line at most every ``every_s`` seconds (while they keep coming).
"""

from __future__ import annotations

import logging
import threading
import time

__all__ = ["Tally"]

#: How often a summary line may be logged while drops go on.
SUMMARY_EVERY_S = 10.0


class Tally:
    """Counts by reason (``counts``, ``total``); logs the first at once, then periodically.

    >>> tally = Tally(logging.getLogger("demo"), "robot e1 refused")
    >>> tally.add("busy", "robot e1 is driven by another controller")
    >>> tally.counts
    {'busy': 1}
    """

    def __init__(
        self, logger: logging.Logger, what: str, *, every_s: float = SUMMARY_EVERY_S
    ) -> None:
        self.logger = logger
        self.what = what
        self.every_s = every_s
        #: How many, by reason, since the start.
        self.counts: dict[str, int] = {}
        self._lock = threading.Lock()
        self._unlogged = 0
        self._last_log = -float("inf")

    @property
    def total(self) -> int:
        with self._lock:
            return sum(self.counts.values())

    def get(self, reason: str, default: int = 0) -> int:
        with self._lock:
            return self.counts.get(reason, default)

    def add(self, reason: str, detail: str, count: int = 1) -> None:
        """Count ``count`` more, and log if nothing was logged for ``every_s`` seconds."""
        now = time.monotonic()
        with self._lock:
            self.counts[reason] = self.counts.get(reason, 0) + count
            self._unlogged += count
            if now - self._last_log < self.every_s:
                return
            unlogged, self._unlogged, self._last_log = self._unlogged, 0, now
        if unlogged == 1:
            self.logger.warning("%s (%s): %s", self.what, reason, detail)
        else:
            self.logger.warning("%s %d more since the last report, the latest (%s): %s; in all: %s",
                                self.what, unlogged, reason, detail, self._summary())  # fmt: skip

    def _summary(self) -> str:
        with self._lock:
            return ", ".join(f"{reason} {count}" for reason, count in sorted(self.counts.items()))
