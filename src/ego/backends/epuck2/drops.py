"""How often the e-puck2's WiFi may drop before ego stops reconnecting: a sans-I/O tally.

A radio that drops every few packets (a weak signal, a crowded channel) was reconnected
for ever: each drop reconnected at once and logged a warning, 222 of each in 25 s, and the
controller was never told (issue 32). Now each drop is counted; the reconnects back off,
the warnings are summarised, and more than :attr:`DropPolicy.max_drops` drops within
:attr:`DropPolicy.window_s` mean the reconnects do not hold: the channel raises
LinkLostError, once, and the owner stops the robot (docs/guide/epuck2.md).
"""

from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass

__all__ = ["DropPolicy", "DropTally", "DropVerdict"]


@dataclass(frozen=True, slots=True)
class DropPolicy:
    """The bound on drops, and how reconnects back off and warnings are summarised."""

    #: More drops than this within ``window_s``: the reconnects do not hold.
    max_drops: int = 5
    window_s: float = 30.0
    #: The first drop of a window reconnects at once (the robot keeps its last speeds
    #: until a command comes); the n-th waits ``first_backoff_s * 2 ** (n - 2)`` first,
    #: at most ``max_backoff_s``.
    first_backoff_s: float = 0.05
    max_backoff_s: float = 1.0
    #: After a warning, the drops that follow are told at most this often, as a count.
    summary_s: float = 10.0


@dataclass(frozen=True, slots=True)
class DropVerdict:
    """What to do about one drop."""

    #: Wait this long before reconnecting.
    backoff_s: float
    #: The reconnects do not hold: raise LinkLostError instead of reconnecting.
    give_up: bool
    #: A warning to log (None: counted, told in a later summary).
    warning: str | None
    #: The drops within the window, this one included.
    recent: int


class DropTally:
    """The drops of one link, fed the time of each (``time.monotonic()``)."""

    def __init__(self, policy: DropPolicy | None = None) -> None:
        self.policy = policy or DropPolicy()
        #: Every drop since the link opened.
        self.total = 0
        self._recent: deque[float] = deque()
        self._untold = 0
        self._told_at = -math.inf

    def dropped(self, now: float, why: str) -> DropVerdict:
        """Count a drop (``why``: what ended the connection) and say what to do."""
        policy = self.policy
        self.total += 1
        while self._recent and now - self._recent[0] > policy.window_s:
            self._recent.popleft()
        self._recent.append(now)
        recent = len(self._recent)
        if recent > policy.max_drops:
            return DropVerdict(0.0, True, None, recent)
        backoff = 0.0 if recent == 1 else policy.first_backoff_s * 2 ** (recent - 2)
        backoff = min(backoff, policy.max_backoff_s)
        if now - self._told_at < policy.summary_s:
            self._untold += 1
            return DropVerdict(backoff, False, None, recent)
        warning = f"connection lost ({why}); reconnecting"
        if self._untold:
            warning += f" ({self._untold} more drops since the last warning, each reconnected)"
        self._untold, self._told_at = 0, now
        return DropVerdict(backoff, False, warning, recent)

    def give_up_message(self, why: str) -> str:
        """The LinkLostError's text when the reconnects do not hold."""
        policy = self.policy
        return (
            f"the connection dropped {len(self._recent)} times within {policy.window_s:g} s "
            f"(more than {policy.max_drops}), {self.total} drops in all: reconnects do not "
            f"hold; last: {why}"
        )
