"""The sequence numbers of ego serve's frames: serial arithmetic and the server's guard
that answers a repeated request from its cache instead of running it twice (no I/O)."""

from __future__ import annotations

import enum

__all__ = [
    "SequenceGuard",
    "Verdict",
    "next_seq",
    "seq_after",
]

_U32 = 0xFFFFFFFF


def seq_after(a: int, b: int) -> bool:
    """Whether sequence number ``a`` comes after ``b`` (serial arithmetic, RFC 1982)."""
    return 0 < ((a - b) & _U32) < 0x80000000


def next_seq(seq: int) -> int:
    """The sequence number after ``seq``: 1, 2, ... 2**32-1, 1 (0 means unsolicited)."""
    return seq % _U32 + 1


class Verdict(enum.Enum):
    """What the server should do with a request, given the sequence numbers it has seen."""

    NEW = "new"  # run it
    REPEAT = "repeat"  # the last request again (its reply was lost): resend the cached reply
    WORKING = "working"  # the request being run right now: say so, run nothing
    STALE = "stale"  # older than the last one: a late duplicate; ignore it


class SequenceGuard:
    """The server's memory of one session's last request, so nothing runs twice.

    >>> guard = SequenceGuard()
    >>> guard.check(1)
    <Verdict.NEW: 'new'>
    >>> guard.begin(1); guard.done(1, b"reply")
    >>> guard.check(1), guard.cached
    (<Verdict.REPEAT: 'repeat'>, b'reply')
    """

    __slots__ = ("_cached", "_last", "_running")

    def __init__(self) -> None:
        self._last: int | None = None
        self._running: int | None = None
        self._cached = b""

    @property
    def cached(self) -> bytes:
        """The encoded reply to the last request that completed."""
        return self._cached

    @property
    def running(self) -> int | None:
        """The request being run now, if any."""
        return self._running

    def check(self, seq: int) -> Verdict:
        if seq == self._running:
            return Verdict.WORKING
        if self._last is None:
            return Verdict.NEW
        if seq == self._last:
            return Verdict.REPEAT
        if seq_after(seq, self._last) and (self._running is None or seq_after(seq, self._running)):
            return Verdict.NEW
        return Verdict.STALE

    def begin(self, seq: int) -> None:
        self._running = seq

    def done(self, seq: int, reply: bytes) -> None:
        if self._running == seq:
            self._running = None
        if self._last is None or seq_after(seq, self._last):
            self._last = seq
            self._cached = reply
