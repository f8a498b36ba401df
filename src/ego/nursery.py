"""The one owner of ego's threads and tasks: a :class:`Nursery` (as trio's) starts them,
and its close does not return quietly while one of them still runs.

* :meth:`Nursery.start_thread` runs a function in a thread of the nursery (never a
  daemon: a daemon is killed mid-write at exit, and nobody learns it was still there);
* :meth:`Nursery.start_timer` runs a :class:`DeadlineTimer`: a function called at a
  deadline on the owner's clock, that answers the next one. It sleeps until then
  (re-armed sooner when the deadline moves closer), where a loop would wake every few
  milliseconds to ask;
* :meth:`Nursery.start_soon` runs a coroutine as a task of the running event loop;
* :meth:`Nursery.close` tells its timers to end and joins every thread until one
  deadline; a thread still alive after it is a :class:`~ego.errors.ThreadLeakError`
  naming it (reported, never forgotten: the handle stays, a second close tries again).
  :meth:`Nursery.aclose` first cancels the tasks and waits for them.

The owner tells its threads to end (closes their socket, sets their event) before it
closes the nursery: the nursery cannot interrupt a thread, it only makes sure none is left.
Python waits for every thread that is not a daemon before it exits, so a nursery whose
owner may be left open by a program (a robot's heartbeat, its dashboard) is given
``at_exit``: how the owner ends its threads. At exit, before Python waits for them, every
nursery still open runs its ``at_exit`` (as :mod:`concurrent.futures` ends its workers),
after the hooks given to :func:`before_owners_at_exit` (the open robots' stop).
A thread or task that fails is logged with the nursery's name; the others go on (one bad
request must not take a server down).

asyncio's own ``TaskGroup`` (3.11) ends the group when one task fails and cannot take
tasks once it is closing; a server wants neither, and ego still runs on 3.10.

>>> nursery = Nursery("example")
>>> done = threading.Event()
>>> thread = nursery.start_thread(done.set, name="example-worker")
>>> nursery.close()
>>> done.is_set(), thread.is_alive()
(True, False)
"""

from __future__ import annotations

import logging
import threading
import time
import weakref
from collections.abc import Callable, Coroutine
from types import TracebackType
from typing import TYPE_CHECKING, Any

from ego.errors import ThreadLeakError

if TYPE_CHECKING:  # imported where a task is started: `import ego` leaves asyncio out
    import asyncio

__all__ = ["DEFAULT_JOIN_S", "DeadlineTimer", "Nursery", "before_owners_at_exit"]

log = logging.getLogger(__name__)

#: How long :meth:`Nursery.close` waits, in all, for its threads to end.
DEFAULT_JOIN_S = 5.0

#: The open nurseries with an ``at_exit``, run when the interpreter exits.
_AT_EXIT: weakref.WeakSet[Nursery] = weakref.WeakSet()


def _end_at_exit() -> None:
    """At interpreter exit, before Python joins the threads that are not daemons: each
    open nursery's owner ends its threads."""
    for nursery in list(_AT_EXIT):
        if not nursery.closed and nursery.at_exit is not None:
            try:
                nursery.at_exit()
            except Exception:
                log.exception("%s: ending its threads at exit failed", nursery.name)


# Run before the interpreter joins its threads; atexit handlers run only after that join.
# (threading's own hook since 3.9, the one concurrent.futures uses.)
threading._register_atexit(_end_at_exit)  # type: ignore[attr-defined]


def before_owners_at_exit(hook: Callable[[], None]) -> None:
    """Run ``hook`` at interpreter exit before every nursery's ``at_exit`` (and before
    Python waits for the threads): what must be done while the owners' threads still run,
    as a robot's stop sent over a link whose reader the link's ``at_exit`` ends.

    threading runs its exit hooks last registered first, and this module registered its
    own as it was imported, before anyone could call this.
    """
    threading._register_atexit(hook)  # type: ignore[attr-defined]


class DeadlineTimer:
    """Calls ``fire(now)`` once ``clock()`` passes the armed deadline, in a thread of its
    own; ``fire`` returns the next deadline (on the same clock) or None to wait until
    :meth:`arm` is called. Start it with :meth:`Nursery.start_timer`."""

    def __init__(
        self, fire: Callable[[float], float | None], clock: Callable[[], float], name: str
    ) -> None:
        self.name = name
        self._fire = fire
        self._clock = clock
        self._wake = threading.Condition(threading.Lock())
        self._at: float | None = None
        self._cancelled = False
        self._poked = False
        #: Times ``fire`` was called, and times it had returned (tests, logs).
        self.fired = 0
        self.looked = 0

    @property
    def deadline(self) -> float | None:
        """The armed deadline on the owner's clock, or None."""
        return self._at

    def arm(self, at: float) -> None:
        """Fire at ``at`` or sooner: a later deadline than the armed one changes nothing
        (``fire`` answers the true next one when it runs)."""
        with self._wake:
            if self._at is None or at < self._at:
                self._at = at
                self._wake.notify()

    def poke(self) -> None:
        """Fire now, whatever the deadline: for a clock that jumps (a test's fake clock),
        which a sleeping timer cannot see move."""
        with self._wake:
            self._poked = True
            self._wake.notify()

    def cancel(self) -> None:
        """End the timer's thread (the nursery's close does it)."""
        with self._wake:
            self._cancelled = True
            self._wake.notify()

    def run(self) -> None:
        """The timer's thread: sleep until the deadline, fire, take the next one."""
        while True:
            with self._wake:
                while not (self._cancelled or self._poked):
                    at = self._at
                    left = None if at is None else at - self._clock()
                    if left is not None and left < 0:  # past it, as the session's tick wants
                        break
                    self._wake.wait(left)
                if self._cancelled:
                    return
                self._at, self._poked = None, False
            self.fired += 1
            try:
                following = self._fire(self._clock())
            except Exception:  # a failing call must not end the timer (a deadman)
                log.exception("timer %s failed", self.name)
                following = None
            if following is not None:
                self.arm(following)
            self.looked += 1


class Nursery:
    """Owns the threads, timers and tasks it starts; see the module's doc."""

    def __init__(
        self, name: str, join_s: float = DEFAULT_JOIN_S, at_exit: Callable[[], None] | None = None
    ) -> None:
        self.name = name
        self.join_s = join_s
        #: How the owner ends these threads, if the program exits with the owner open.
        self.at_exit = at_exit
        if at_exit is not None:
            _AT_EXIT.add(self)
        self._threads: list[threading.Thread] = []
        self._starting: set[threading.Thread] = set()
        self._timers: list[DeadlineTimer] = []
        self._tasks: set[asyncio.Task[None]] = set()
        self._lock = threading.Lock()
        self._closed = False

    def __len__(self) -> int:
        """How many of its threads and tasks still run."""
        return len(self._tasks) + sum(t.is_alive() for t in self._threads)

    @property
    def closed(self) -> bool:
        return self._closed

    # -- threads ---------------------------------------------------------------------------

    def start_thread(
        self, target: Callable[..., object], *args: Any, name: str
    ) -> threading.Thread:
        """Run ``target(*args)`` in a new thread of this nursery; its failure is logged."""

        def child() -> None:
            try:
                target(*args)
            except BaseException:
                log.exception("%s: thread %s failed", self.name, name)

        thread = threading.Thread(target=child, name=name)
        with self._lock:
            if self._closed:
                raise RuntimeError(f"{self.name} is closed: thread {name} not started")
            # The ended ones are let go (an owner that starts a thread a step keeps only
            # those still running); one still starting is not alive yet, and is kept.
            self._threads = [t for t in self._threads if t in self._starting or t.is_alive()]
            self._threads.append(thread)
            self._starting.add(thread)
        try:
            thread.start()
        finally:
            with self._lock:
                self._starting.discard(thread)
        return thread

    def start_timer(
        self,
        fire: Callable[[float], float | None],
        *,
        name: str,
        clock: Callable[[], float] = time.monotonic,
    ) -> DeadlineTimer:
        """A :class:`DeadlineTimer` calling ``fire`` on ``clock``, unarmed, in a thread of
        this nursery (ended by :meth:`close`)."""
        timer = DeadlineTimer(fire, clock, name)
        self._timers.append(timer)
        self.start_thread(timer.run, name=name)
        return timer

    def close(self, join_s: float | None = None) -> None:
        """Take no more threads, end the timers and join every thread within ``join_s``
        seconds in all (:attr:`join_s` by default); idempotent.

        Raises :class:`~ego.errors.ThreadLeakError` naming the threads still alive then
        (they stay in the nursery: a later close joins them again). A thread that closes
        its own nursery is not waited for: it ends as it returns.
        """
        with self._lock:
            self._closed = True
            threads = list(self._threads)
        for timer in self._timers:
            timer.cancel()
        deadline = time.monotonic() + (self.join_s if join_s is None else join_s)
        me = threading.current_thread()
        for thread in threads:
            if thread is not me and thread.ident is not None:
                thread.join(max(0.0, deadline - time.monotonic()))
        with self._lock:
            self._threads = [t for t in self._threads if t in self._starting or t.is_alive()]
            alive = [t.name for t in self._threads if t is not me]
        if alive:
            raise ThreadLeakError(
                f"{self.name}: {len(alive)} thread(s) still running "
                f"{self.join_s if join_s is None else join_s:g} s after close: {', '.join(alive)}"
            )

    def __enter__(self) -> Nursery:
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        self.close()

    # -- asyncio tasks -----------------------------------------------------------------------

    def start_soon(self, work: Coroutine[Any, Any, None]) -> None:
        """Run ``work`` as a task of this nursery (on the running loop); once the nursery
        is closing, ``work`` is closed unrun."""
        if self._closed:
            work.close()
            return
        import asyncio

        task = asyncio.get_running_loop().create_task(work)
        self._tasks.add(task)
        task.add_done_callback(self._finished)

    def _finished(self, task: asyncio.Task[None]) -> None:
        self._tasks.discard(task)
        if not task.cancelled() and task.exception() is not None:
            log.error("%s: a task failed", self.name, exc_info=task.exception())

    async def aclose(self, join_s: float | None = None) -> None:
        """Take no more tasks, cancel the running ones and wait until all have ended, then
        :meth:`close` (its threads joined off the loop)."""
        import asyncio

        self._closed = True
        while self._tasks:
            tasks = list(self._tasks)
            for task in tasks:
                task.cancel()
            await asyncio.gather(*tasks, return_exceptions=True)
        if self._threads:
            await asyncio.to_thread(self.close, join_s)
        else:
            self.close(join_s)
