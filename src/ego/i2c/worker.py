"""The Overo's I2C transfers on a thread of their own, so that a caller waits a bounded time.

An i2c-dev transfer blocks in the kernel until the adapter's driver gives up, and the
OMAP3's gives up only after a second (``OMAP_I2C_TIMEOUT``, 1000 ms, in
torvalds/linux drivers/i2c/busses/i2c-omap.c), which the ``I2C_TIMEOUT`` ioctl does not
shorten there. A step cannot wait that long (issue 32): each transfer runs on the bus's
worker thread and its caller waits until its own deadline; past it, the caller goes on
without the reading (None: a late transfer, on a loaded board, is no fault). The transfer
left running keeps the bus: later ones get None at once until it returns, and once it
has held the bus for :data:`HUNG_S` it has hung: LinkTimeoutError. The worker is a
thread of the bus's :class:`~ego.nursery.Nursery`, started at the first transfer and
stopped and joined by :meth:`BusWorker.close` (which waits for a transfer still running:
the kernel ends it; one still running :data:`~ego.nursery.DEFAULT_JOIN_S` later is a
ThreadLeakError). A program that exits with the bus open has it closed before Python
waits for its threads.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
from typing import Generic, TypeVar

from ego.errors import LinkTimeoutError
from ego.nursery import Nursery

__all__ = ["HUNG_S", "BusWorker"]

T = TypeVar("T")

#: A transfer that holds the bus this long has hung: the OMAP3's driver gives up on a
#: message after 1 s (OMAP_I2C_TIMEOUT), so a working bus never takes longer.
HUNG_S = 1.0


class _Job(Generic[T]):
    def __init__(self, work: Callable[[], T]) -> None:
        self.work = work
        self.done = threading.Event()
        self.value: T | None = None
        self.error: BaseException | None = None

    def run(self) -> None:
        try:
            self.value = self.work()
        except BaseException as exc:  # handed to the caller, whatever it was
            self.error = exc
        finally:
            self.done.set()


class BusWorker:
    """Runs one transfer at a time for the bus called ``name``."""

    def __init__(self, name: str) -> None:
        self.name = name
        self._cond = threading.Condition()
        self._job: _Job[object] | None = None
        self._running: _Job[object] | None = None
        #: When the transfer holding the bus was handed to the worker (time.monotonic()).
        self._held_since = 0.0
        self._stopping = False
        self._nursery = Nursery(name, at_exit=self.close)
        self._started = False

    def run(self, work: Callable[[], T], deadline_s: float, what: str) -> T | None:
        """``work()``'s result, or its error; None if it has not returned by ``deadline_s``
        (time.monotonic()), or while an earlier late transfer still holds the bus;
        LinkTimeoutError once that one has held it for :data:`HUNG_S`."""
        job: _Job[T] = _Job(work)
        with self._cond:
            if self._stopping:
                raise LinkTimeoutError(f"{self.name} is closed")
            if self._running is not None or self._job is not None:
                held_s = time.monotonic() - self._held_since
                if held_s >= HUNG_S:
                    raise LinkTimeoutError(
                        f"{self.name}: {what}: the bus has been held {held_s:.1f} s by a "
                        f"transfer that does not end (no answer within {HUNG_S:.0f} s)"
                    )
                return None
            if not self._started:
                self._nursery.start_thread(self._serve, name="ego-i2c-bus")
                self._started = True
            self._job = job  # type: ignore[assignment]
            self._held_since = time.monotonic()
            self._cond.notify_all()
        if not job.done.wait(max(0.0, deadline_s - time.monotonic())):
            return None
        if job.error is not None:
            raise job.error
        return job.value

    def close(self) -> None:
        """Stop the thread and join it (after a transfer still running ends; one still
        running :data:`~ego.nursery.DEFAULT_JOIN_S` later is a ThreadLeakError); idempotent."""
        with self._cond:
            self._stopping = True
            self._cond.notify_all()
        self._nursery.close()

    def _serve(self) -> None:
        while True:
            with self._cond:
                while self._job is None and not self._stopping:
                    self._cond.wait()
                if self._job is None:
                    return
                job, self._job = self._job, None
                self._running = job
            job.run()
            with self._cond:
                self._running = None
