"""The one control session both servers run: the lease, the deadman, the dispatch (no I/O).

``ego serve`` over sockets (:mod:`ego.servers.sessions.session`, its frames and
handshake) and the Zenoh node (:mod:`ego.servers.zenoh_node.node`, its queries and
puts) both hand what their clients did to a :class:`ControlSession`, with the time, and
act on what it answers, as h11's connection is fed events and returns events:

* the lease: one holder at a time (a socket session id, a Zenoh controller id); another
  is refused (:attr:`Refusal.BUSY`) until the holder lets go or the deadman frees it;
* one request in flight: a holder's call that comes while another of its calls runs is
  refused (:attr:`Refusal.IN_FLIGHT`), never queued, so that nothing it stacked up
  outlives it;
* the deadman: once the holder has been silent for more than ``deadline_s`` (nothing
  new: a request, a keepalive, a call that ended) while none of its calls runs,
  :meth:`tick` frees the robot and says so (:class:`Lapsed`); the adapter stops it.

It never reads a clock: every event carries ``now`` (seconds, any monotonic origin).

>>> control = ControlSession[str](deadline_s=0.5)
>>> control.take("a", now=0.0), control.take("b", now=0.1)
(True, False)
>>> control.dispatch("a", now=0.2), control.dispatch("a", now=0.3)
(None, <Refusal.IN_FLIGHT: 'in flight'>)
>>> control.completed("a", now=0.4), control.tick(now=0.9), control.tick(now=0.91).holder
(True, None, 'a')
"""

from __future__ import annotations

import enum
from collections.abc import Hashable
from dataclasses import dataclass
from typing import Generic, TypeVar

__all__ = ["ControlSession", "Lapsed", "Refusal"]

H = TypeVar("H", bound=Hashable)


class Refusal(str, enum.Enum):
    """Why a call was not dispatched."""

    #: Another holds the robot.
    BUSY = "busy"
    #: The holder's previous call still runs.
    IN_FLIGHT = "in flight"


@dataclass(frozen=True, slots=True)
class Lapsed(Generic[H]):
    """The deadman freed the robot: ``holder`` had been silent ``silent_s`` seconds."""

    holder: H
    silent_s: float
    deadline_s: float

    @property
    def why(self) -> str:
        return (
            f"silent for {self.silent_s * 1e3:.0f} ms (deadline {self.deadline_s * 1e3:.0f} ms)"
        )


class ControlSession(Generic[H]):
    """Who holds the robot, when they were last heard, and whether a call of theirs runs."""

    def __init__(self, deadline_s: float) -> None:
        self.deadline_s = deadline_s
        self.holder: H | None = None
        self.last_heard = 0.0
        #: How many of the holder's calls run now (0 or 1: one in flight).
        self.in_flight = 0
        #: Times the deadman freed the robot.
        self.lapses = 0

    def holds(self, who: H) -> bool:
        return self.holder is not None and self.holder == who

    # -- events --------------------------------------------------------------------------

    def take(self, who: H, now: float) -> bool:
        """``who`` wants the robot: theirs if free (or already theirs); False if another's."""
        if self.holder is not None and self.holder != who:
            return False
        if self.holder is None:
            self.holder, self.in_flight = who, 0
        self.last_heard = now
        return True

    def admit(self, who: H, now: float) -> bool:
        """A request of ``who`` arrives: False if another holds the robot; if ``who`` holds
        it, it was heard (nothing is taken until the request runs)."""
        if self.holder is not None and self.holder != who:
            return False
        self.heard(who, now)
        return True

    def heard(self, who: H, now: float) -> None:
        """Something new from ``who`` (a request, a keepalive): the deadman waits anew."""
        if self.holds(who):
            self.last_heard = now

    def dispatch(self, who: H, now: float) -> Refusal | None:
        """A call of ``who`` is to run: None if it may (it is in flight until
        :meth:`completed`), else why not. Only the holder's calls run, one at a time."""
        if not self.holds(who):
            return Refusal.BUSY
        if self.in_flight:
            return Refusal.IN_FLIGHT
        self.in_flight, self.last_heard = 1, now
        return None

    def completed(self, who: H, now: float) -> bool:
        """A call of ``who`` ended; False if ``who`` no longer holds the robot (the reply
        has nobody to go to)."""
        if not self.holds(who):
            return False
        self.in_flight, self.last_heard = 0, now
        return True

    def release(self, who: H) -> bool:
        """``who`` lets go (a goodbye, a lost connection); whether they held the robot."""
        if not self.holds(who):
            return False
        self.holder, self.in_flight = None, 0
        return True

    def tick(self, now: float) -> Lapsed[H] | None:
        """Time passed: the robot freed if its holder has been silent past the deadline
        while none of its calls ran (a call may wait on a retrying serial line)."""
        holder = self.holder
        if holder is None or self.in_flight:
            return None
        silent_s = now - self.last_heard
        if silent_s <= self.deadline_s:
            return None
        self.holder, self.lapses = None, self.lapses + 1
        return Lapsed(holder, silent_s, self.deadline_s)

    def due_at(self) -> float | None:
        """When the deadman is due (on the clock the events carry); None while nobody holds
        the robot or a call of the holder runs."""
        if self.holder is None or self.in_flight:
            return None
        return self.last_heard + self.deadline_s

    def due_in(self, now: float) -> float | None:
        """Seconds until the deadman is due (<= 0: due now); None while nobody holds the
        robot or a call of the holder runs."""
        if self.holder is None or self.in_flight:
            return None
        return self.last_heard + self.deadline_s - now
