"""The serial line's one owner in a robot node: a worker thread that runs the node's jobs
one at a time, the stop ahead of all of them.

Zenoh's threads only queue a job (a batch, an ASCII command); the worker runs them in
order. When the deadman (or a bye) asks for the stop, the worker runs it as soon as the
job in hand ends, before any job still queued: the stop never waits behind a queue. A
job in hand is bounded (a batch takes milliseconds; an ASCII query asks for at most two
lines), so the stop waits at most for that one.
"""

from __future__ import annotations

import logging
import threading
from collections import deque
from collections.abc import Callable
from typing import Protocol

from ego.nursery import Nursery

__all__ = ["Job", "LineWorker"]

log = logging.getLogger(__name__)

#: How many jobs may wait; more are refused (a flood).
DEFAULT_CAPACITY = 64


class Job(Protocol):
    """What the worker runs: ``run()`` on the line, or ``cancel(why)`` if it never will."""

    who: str

    def run(self) -> None: ...

    def cancel(self, why: str) -> None: ...


class LineWorker:
    """Runs ``Job``\\ s in one thread, and ``stop`` ahead of them when asked."""

    def __init__(
        self,
        stop: Callable[[], None],
        *,
        name: str,
        capacity: int = DEFAULT_CAPACITY,
        nursery: Nursery | None = None,
    ) -> None:
        self._stop = stop
        self.name = name
        self.capacity = capacity
        self._jobs: deque[Job] = deque()
        self._wake = threading.Condition()
        self._stop_wanted = False
        self._closing = False
        #: Its thread's owner: the node's nursery, or one of its own that close() closes.
        self._own = nursery is None
        self._nursery = Nursery(name, join_s=2.0) if nursery is None else nursery

    def start(self) -> LineWorker:
        self._nursery.start_thread(self._work, name=self.name)
        return self

    def submit(self, job: Job) -> bool:
        """Queue ``job``; False (not queued) if the queue is full or the worker closing."""
        with self._wake:
            if self._closing or len(self._jobs) >= self.capacity:
                return False
            self._jobs.append(job)
            self._wake.notify()
        return True

    def request_stop(self, drop: Callable[[Job], bool] = lambda job: False) -> list[Job]:
        """Run the stop before any queued job; the queued jobs ``drop`` picks are taken out
        and returned (unanswered: the caller cancels them, outside the worker's lock)."""
        with self._wake:
            self._stop_wanted = True
            dropped = [job for job in self._jobs if drop(job)]
            for job in dropped:
                self._jobs.remove(job)
            self._wake.notify()
        return dropped

    def close(self, why: str) -> None:
        """End the worker once the job in hand is done; the queued ones are cancelled. A
        worker with a nursery of its own is joined here (a job in hand that does not end
        within 2 s is a :class:`~ego.errors.ThreadLeakError`); else its owner joins it."""
        with self._wake:
            self._closing = True
            left, self._jobs = list(self._jobs), deque()
            self._wake.notify()
        for job in left:
            job.cancel(why)
        if self._own:
            self._nursery.close()

    def _next(self) -> Job | None:
        """The next job, None for the stop; raises StopIteration when closing."""
        with self._wake:
            while not (self._stop_wanted or self._jobs or self._closing):
                self._wake.wait()
            if self._closing:
                raise StopIteration
            if self._stop_wanted:
                self._stop_wanted = False
                return None
            return self._jobs.popleft()

    def _work(self) -> None:
        while True:
            try:
                job = self._next()
            except StopIteration:
                return
            try:
                if job is None:
                    self._stop()
                else:
                    job.run()
            except Exception:  # a bug: logged with its traceback; the line stays served
                log.exception("robot node: %s failed", "the stop" if job is None else "a job")
