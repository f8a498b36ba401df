"""Time steps against an absolute deadline: no drift, a precise sleep, overruns counted.

Each step's deadline is the previous one plus the step, so a late wake-up does not
push every later step back. The wait sleeps until shortly before the deadline and
spins the rest, because ``time.sleep`` on Linux overshoots by 50-100 us, which is 5-10 %
of a 1 ms step. An overrun (the step's work took longer than the step) re-anchors
the deadline to now instead of rushing the following steps to catch up.

Two settings make short steps precise but belong to the whole process, so a clock never
changes them by itself (library manners): :func:`tune_for_stepping` asks Linux for a
1 us timer slack on the calling thread instead of the default 50 us, and shortens the
interpreter's thread switch interval. ``ego run`` and ``ego demo`` call it; a program of
your own may.
"""

from __future__ import annotations

import ctypes
import logging
import sys
import time
from collections.abc import Callable
from typing import Protocol

from ego.core.overrun_report import OverrunReport

__all__ = ["Pacer", "StepClock", "tune_for_stepping"]

log = logging.getLogger(__name__)


class Pacer(Protocol):
    """What paces a robot's steps: the wall clock (:class:`StepClock`), or an emulator's
    virtual time, which a step moves on at once (``ego run --port sim --fast``)."""

    overruns: int
    worst_overrun_s: float

    def begin(self) -> None: ...

    def wait(self, step_ms: float) -> bool:
        """Let the step's time pass; True if it had already overrun."""
        ...

    def close(self) -> None: ...


class StepClock:
    """Waits out time steps; ``overruns`` counts the steps whose work ran past their deadline.

    >>> clock = StepClock()
    >>> for _ in range(3):
    ...     clock.wait(1)  # returns False: nothing ran late
    False
    False
    False
    """

    def __init__(
        self,
        spin_s: float | None = None,
        clock: Callable[[], float] = time.perf_counter,
        sleep: Callable[[float], None] = time.sleep,
    ) -> None:
        #: How long before the deadline the sleep ends and the spin begins. None: learnt
        #: from how late this thread's sleeps wake (:class:`SpinGauge`); a number: fixed.
        self._gauge = SpinGauge() if spin_s is None else None
        self.spin_s = spin_s if spin_s is not None else self._gauge.spin_s  # type: ignore[union-attr]
        self._clock = clock
        self._sleep = sleep
        self._deadline: float | None = None
        self.overruns = 0
        self.worst_overrun_s = 0.0
        self._report = OverrunReport()

    def begin(self) -> None:
        """Anchor the first deadline at the start of the first step."""
        if self._deadline is None:
            self._deadline = self._clock()

    def wait(self, step_ms: float) -> bool:
        """Wait until this step's deadline; True if the step had already overrun it."""
        self.begin()
        assert self._deadline is not None
        deadline = self._deadline + step_ms / 1000.0
        now = self._clock()
        if now > deadline:
            late = now - deadline
            self.overruns += 1
            self.worst_overrun_s = max(self.worst_overrun_s, late)
            line = self._report.note(now, step_ms, late)
            if line is not None:
                log.warning("%s", line)
            self._deadline = now
            return True
        remaining = deadline - now
        if remaining > self.spin_s:
            wake = now + remaining - self.spin_s
            self._sleep(remaining - self.spin_s)
            if self._gauge is not None:
                self.spin_s = self._gauge.woke(self._clock() - wake)
        while self._clock() < deadline:
            pass
        self._deadline = deadline
        return False

    def close(self) -> None:
        line = self._report.flush(self._clock())
        if line is not None:
            log.warning("%s", line)


class SpinGauge:
    """How long to spin before a deadline: a little more than this thread's sleeps wake late.

    ``time.sleep`` wakes late by the timer slack and the scheduler's latency (a median of
    44 us, 68 us at the 99th percentile with a 1 us slack; 50-100 us more without). A spin
    longer than that lateness only burns CPU; a shorter one lets the step end late. The
    gauge keeps a slowly decaying maximum of the lateness seen and spins 1.5 times that,
    within 30 us .. 400 us.
    """

    MIN_S = 0.00003
    MAX_S = 0.0004
    #: Per sleep: the remembered worst lateness shrinks by 0.5 %, so one rare late wake
    #: keeps the spin long for a few hundred steps, then lets it shrink again.
    DECAY = 0.995

    def __init__(self) -> None:
        self._late_s = self.MAX_S / 1.5  # start as cautious as the fixed spin was

    @property
    def spin_s(self) -> float:
        return min(self.MAX_S, max(self.MIN_S, 1.5 * self._late_s))

    def woke(self, late_s: float) -> float:
        """One sleep woke ``late_s`` after it asked; the spin to use from now on."""
        self._late_s = max(max(late_s, 0.0), self._late_s * self.DECAY)
        return self.spin_s


#: prctl(2): the calling thread's timer slack, in nanoseconds.
PR_SET_TIMERSLACK = 29
TIMER_SLACK_NS = 1000


def _tighten_timer_slack() -> None:
    """Let this thread's sleeps end within 1 us of their time (Linux; elsewhere a no-op)."""
    if not sys.platform.startswith("linux"):
        return
    try:
        libc = ctypes.CDLL(None, use_errno=True)
        libc.prctl(PR_SET_TIMERSLACK, ctypes.c_ulong(TIMER_SLACK_NS), 0, 0, 0)
    except (OSError, AttributeError):  # no libc to ask: keep the default slack
        log.debug("could not set the timer slack")


#: The switch interval ``ego run`` uses: a 1 ms step waits at most this for the GIL.
STEPPING_SWITCH_INTERVAL_S = 0.0002


#: The real-time priority ``realtime=True`` asks for: the lowest of SCHED_FIFO's, above
#: every ordinary process and below the kernel's own real-time threads.
REALTIME_PRIORITY = 1


def tune_for_stepping(realtime: bool = False) -> None:
    """Make the calling thread's steps precise: 1 us timer slack, a 0.2 ms switch interval.

    Both are process settings (the slack is the calling thread's, the interval the
    interpreter's), so only a program that owns the process asks for them: ``ego run``
    and ``ego demo`` do, before the controller starts.

    ``realtime`` (``ego run --realtime``) also puts the calling thread on SCHED_FIFO at
    priority 1: other processes can no longer hold the core through a step's deadline
    (benchmarks/results/performance.md: 99-100 % of 5 ms steps within 5 % under load,
    against 78-97 % without). Off by default: a controller stuck in a loop at that
    priority starves everything else on a one-core Overo, ssh included. It needs root,
    CAP_SYS_NICE or an RLIMIT_RTPRIO of 1; without them it raises EgoError saying so.
    """
    _tighten_timer_slack()
    if sys.getswitchinterval() > STEPPING_SWITCH_INTERVAL_S:
        sys.setswitchinterval(STEPPING_SWITCH_INTERVAL_S)
    if realtime:
        _run_in_realtime()


def _run_in_realtime() -> None:
    import os

    from ego.errors import EgoError

    try:
        os.sched_setscheduler(0, os.SCHED_FIFO, os.sched_param(REALTIME_PRIORITY))
    except (AttributeError, OSError) as exc:  # no SCHED_FIFO here, or not permitted
        raise EgoError(
            f"--realtime: cannot run the controller on SCHED_FIFO ({exc}); it needs root, "
            "CAP_SYS_NICE, or 'ulimit -r 1' (rtprio 1 in /etc/security/limits.conf)"
        ) from exc
