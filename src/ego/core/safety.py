"""Stopping the robot however a controller ends: the stop batch, signals, and who holds robots.

A controller can end in many ways: it returns, it raises, its ``Robot`` is dropped
without ``close()``, the interpreter exits, or a signal arrives (Ctrl-C, ``kill``, an
ssh session to the robot hanging up). In every one of them, short of SIGKILL or power
loss, the dsPIC must be told to stop the wheels and switch its LEDs off, because the
firmware itself has no watchdog: it keeps the last speeds it was given forever.

Three mechanisms, each covering what the others cannot:

- every open link carries a :func:`weakref.finalize` that sends the stop batch when its
  ``Robot`` is garbage-collected; at interpreter exit, every robot still open is closed
  (stopped, its threads ended) before Python waits for the threads that are not daemons,
  where a finalizer would come only after that wait, and never if a robot's own reader
  thread were what it waits for (and before any :class:`~ego.nursery.Nursery`'s
  ``at_exit`` ends a link the stop goes through);
- :func:`install_signal_handlers` turns every asynchronous signal whose default action
  ends the process into a :class:`SignalExit`, so that ``with`` blocks and finalizers run
  before the process ends with the conventional status 128 + signal number;
- :class:`RobotKeeper` (what ``ego run`` uses) holds strong references to each robot
  opened while it is active and stops them itself, so that nothing depends on the order
  in which a finished controller's globals are torn down.

Who holds the robots is one explicit object, :data:`OPEN_ROBOTS` (an :class:`OpenRobots`):
the robots open in this process (weakly) and the keepers active in it. A ``Robot`` tells
it when it opens and when it closes; nothing else in ego keeps a registry of robots.
"""

from __future__ import annotations

import contextlib
import logging
import signal
import threading
import weakref
from types import FrameType
from typing import TYPE_CHECKING, Protocol

from ego.nursery import before_owners_at_exit
from ego.seam.batch import Request
from ego.seam.profile import Command
from ego.serial.protocol import encode_batch

if TYPE_CHECKING:
    from ego.seam.channel import Channel

__all__ = [
    "OPEN_ROBOTS",
    "TERMINATING_SIGNALS",
    "OpenRobots",
    "RobotKeeper",
    "SignalExit",
    "install_signal_handlers",
    "send_stop",
    "stop_requests",
]

log = logging.getLogger(__name__)

#: Tries at a confirmed stop before giving up (a reset or a garbled reply costs one).
STOP_ATTEMPTS = 3


def stop_requests(leds: tuple[int, ...], rgb_leds: tuple[int, ...] = ()) -> list[Request]:
    """Wheels to 0, each of ``leds`` off (and the RGB ones, the e-puck2's, black), then
    ``E`` so that the dsPIC must answer."""
    black = [Request(Command.RGB_LEDS, (0,) * 3 * len(rgb_leds))] if rgb_leds else []
    return [
        Request(Command.SET_SPEED, (0, 0)),
        *(Request(Command.SET_LED, (i, 0)) for i in leds),
        *black,
        Request(Command.GET_SPEED),
    ]


def send_stop(link: Channel) -> None:
    """Send the stop batch until the dsPIC confirms its speeds are (0, 0).

    The batch ends with ``E``, so the stop is known to have been heard; it raises
    ProtocolError when no attempt is confirmed, or the link's own error when it is gone.
    """
    from ego.errors import ProtocolError, RobotResetError

    for _ in range(STOP_ATTEMPTS):
        profile = link.profile
        batch = encode_batch(stop_requests(profile.leds, profile.rgb_leds), profile)
        try:
            held = batch.decode(link.exchange(batch))[-1]
        except RobotResetError:
            continue  # a restarted dsPIC stands still with its LEDs off; confirm anyway
        if tuple(held) == (0, 0):
            return
    raise ProtocolError("the robot did not confirm that its motors stopped")


# -- signals ------------------------------------------------------------------------------


class SignalExit(SystemExit):
    """Raised in the main thread by a terminating signal, so that cleanup code runs.

    Its exit status is 128 + the signal's number, as a shell reports a process killed by
    that signal. It derives from SystemExit so that ``except Exception`` in a controller
    does not swallow it.
    """

    def __init__(self, signum: int) -> None:
        super().__init__(128 + signum)
        self.signum = signum

    def __str__(self) -> str:
        return f"stopped by {signal.Signals(self.signum).name}"


def _terminating_signals() -> tuple[signal.Signals, ...]:
    """Asynchronous signals whose default action ends the process (signal(7)).

    SIGINT is left out: Python already turns it into KeyboardInterrupt. SIGKILL and SIGSTOP
    cannot be caught; SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGTRAP and SIGABRT report a
    fault of the process itself, after which running Python code is not safe.
    """
    names = (
        "SIGHUP", "SIGTERM", "SIGQUIT", "SIGUSR1", "SIGUSR2", "SIGALRM", "SIGPIPE",
        "SIGVTALRM", "SIGPROF", "SIGXCPU", "SIGXFSZ", "SIGIO", "SIGPWR", "SIGSYS",
    )  # fmt: skip
    return tuple(getattr(signal, name) for name in names if hasattr(signal, name))


TERMINATING_SIGNALS = _terminating_signals()

_installed: set[int] = set()
_exiting = False


def _on_terminating_signal(signum: int, frame: FrameType | None) -> None:
    global _exiting
    if _exiting:
        # A second signal while the first one's cleanup runs must not cut the stop
        # batch short; the process ends as soon as that cleanup is done.
        log.warning("%s received while stopping the robot; still stopping",
                    signal.Signals(signum).name)  # fmt: skip
        return
    _exiting = True
    raise SignalExit(signum)


def install_signal_handlers() -> bool:
    """Make each terminating signal unwind the main thread (once; main thread only).

    Only signals still at their default action are taken: a handler the application
    installed itself is left alone, and so are SIGPIPE and SIGXFSZ, which Python ignores
    at start-up (a write to a closed pipe, or past the file size limit, then raises an
    OSError, which unwinds as any error does). Returns whether the handlers are in place.
    """
    if threading.current_thread() is not threading.main_thread():
        return False
    for sig in TERMINATING_SIGNALS:
        if sig in _installed and signal.getsignal(sig) is _on_terminating_signal:
            continue
        _installed.discard(sig)  # taken back by someone since: ask again
        with contextlib.suppress(OSError, ValueError):  # a signal this kernel refuses
            if signal.getsignal(sig) is signal.SIG_DFL:
                signal.signal(sig, _on_terminating_signal)
                _installed.add(sig)
    return True


def uninstall_signal_handlers() -> None:
    """Give back the default action to each signal :func:`install_signal_handlers` took."""
    global _exiting
    for sig in list(_installed):
        if signal.getsignal(sig) is _on_terminating_signal:
            signal.signal(sig, signal.SIG_DFL)
        _installed.discard(sig)
    _exiting = False


# -- who holds the robots ----------------------------------------------------------------


class Closable(Protocol):
    def close(self) -> None: ...


class OpenRobots:
    """The robots open in this process (held weakly: dropping one still stops it), and
    the keepers active in it, which hold each robot opened meanwhile strongly."""

    def __init__(self) -> None:
        self._open: weakref.WeakSet[Closable] = weakref.WeakSet()
        self._keepers: list[RobotKeeper] = []
        self._lock = threading.Lock()

    def opened(self, robot: Closable) -> None:
        """A robot opened: count it, and hand it to every active keeper."""
        with self._lock:
            self._open.add(robot)
            for keeper in self._keepers:
                keeper.robots.append(robot)

    def closed(self, robot: Closable) -> None:
        """A robot closed (its keepers close it again harmlessly: close is idempotent)."""
        with self._lock:
            self._open.discard(robot)

    def robots(self) -> list[Closable]:
        """The robots open now."""
        with self._lock:
            return list(self._open)

    def close_all(self) -> None:
        """Close every robot still open (each one stops first); one failing spares none."""
        for robot in self.robots():
            try:
                robot.close()
            except Exception:
                log.exception("could not close %r", robot)

    def _enter(self, keeper: RobotKeeper) -> None:
        with self._lock:
            self._keepers.append(keeper)

    def _leave(self, keeper: RobotKeeper) -> None:
        with self._lock:
            self._keepers.remove(keeper)


class RobotKeeper:
    """Strong references to every robot opened while it is active; stops them on exit.

    >>> with RobotKeeper() as kept:                    # doctest: +SKIP
    ...     run_the_controller()                       # its robots go into kept.robots
    ...                                                # leaving the block closes them

    Robots reach it through ``registry`` (:data:`OPEN_ROBOTS`, where each Robot says it
    opened); keepers nest.
    """

    def __init__(self, registry: OpenRobots | None = None) -> None:
        self.robots: list[Closable] = []
        self._registry = registry if registry is not None else OPEN_ROBOTS

    def __enter__(self) -> RobotKeeper:
        self._registry._enter(self)
        return self

    def __exit__(self, *exc_info: object) -> None:
        self._registry._leave(self)
        self.close_all()

    def close_all(self) -> None:
        """Close each kept robot, newest first; one that fails does not spare the others."""
        while self.robots:
            robot = self.robots.pop()
            try:
                robot.close()
            except Exception:
                log.exception("could not close %r", robot)


#: The robots of this process and its active keepers: the one registry of robots.
OPEN_ROBOTS = OpenRobots()
# At exit, before Python joins the threads, and before the nurseries' owners end theirs
# (a WiFi link's reader, an I2C bus's worker): each robot's stop still gets through.
before_owners_at_exit(OPEN_ROBOTS.close_all)
