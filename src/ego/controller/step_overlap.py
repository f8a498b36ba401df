"""Webots' ``stepBegin``/``stepEnd``: the step's exchange with the robot runs while the
controller computes.

Webots added the pair so that a controller works while the simulator steps. Here the
link is the slow part: :meth:`StepOverlap.begin` starts the whole step (the batch out,
the replies in, the pacing wait) in a thread of its own and returns at once;
:meth:`StepOverlap.end` waits for it and gives its result. A controller that computes
``work`` ms a step then steps in about max(wire, work) instead of wire + work
(benchmarks/step_overlap.py measures it).

Between the two calls the controller's commands go to the next batch, as in Webots; its
sensor reads may already give this step's values for the families already answered
(Webots gives the last step's until ``stepEnd``): read them after ``stepEnd``.

While a step is in flight the interpreter switches threads every 0.5 ms instead of 5
(:data:`STEP_SWITCH_INTERVAL_S`), so that the step thread gets the GIL as its reply
bytes arrive while the controller computes in Python; ``stepEnd`` puts it back.

The thread is the Robot's, in a :class:`~ego.nursery.Nursery`: ``end`` joins it, and so
does the robot's close (a step in flight when the controller fails or the run ends is
waited for, never left running), as does a program's exit with the robot still open,
before Python waits for its threads. Once closed, a step begun runs at once in the
caller (the robot's step, closed, only says so).
"""

from __future__ import annotations

import sys
import threading
from collections.abc import Callable

from ego.nursery import Nursery

__all__ = ["STEP_SWITCH_INTERVAL_S", "StepOverlap"]

#: The interpreter's thread switch interval while a step is in flight (its default is
#: 5 ms): the step thread wakes each time reply bytes arrive, and a controller computing
#: in Python holds the GIL; without this, each wake could wait 5 ms for it.
STEP_SWITCH_INTERVAL_S = 0.0005


class StepOverlap:
    """One step at a time in flight, run by ``step`` (the Robot's own ``step``)."""

    def __init__(self, step: Callable[[int | None], int]) -> None:
        self._step = step
        self._nursery = Nursery("ego-step", at_exit=self.close)
        self._thread: threading.Thread | None = None
        #: A step begun and not yet ended (in its thread, or run at once once closed).
        self._begun = False
        self._result = 0
        self._error: BaseException | None = None
        self._saved_interval = sys.getswitchinterval()

    @property
    def in_flight(self) -> bool:
        return self._thread is not None

    def begin(self, duration: int | None) -> None:
        """Start a step of ``duration`` ms; one begun and not ended is ended first."""
        if self._begun:
            self.end()
        self._result, self._error, self._begun = 0, None, True
        self._saved_interval = sys.getswitchinterval()
        sys.setswitchinterval(min(self._saved_interval, STEP_SWITCH_INTERVAL_S))
        try:
            self._thread = self._nursery.start_thread(self._run, duration, name="ego-step")
        except RuntimeError:
            sys.setswitchinterval(self._saved_interval)
            if not self._nursery.closed:
                raise
            self._run(duration)  # the robot closed: its step says so at once

    def _run(self, duration: int | None) -> None:
        try:
            self._result = self._step(duration)
        except BaseException as exc:  # raised again by end(), in the caller
            self._error = exc

    def end(self) -> int:
        """Wait for the step begun, and give its result (its error raised here); 0 when
        none was begun."""
        thread, self._thread = self._thread, None
        begun, self._begun = self._begun, False
        if not begun:
            return 0
        if thread is not None:
            thread.join()
            sys.setswitchinterval(self._saved_interval)
        error, self._error = self._error, None
        if error is not None:
            raise error
        return self._result

    def close(self) -> None:
        """Wait for a step still in flight (its error, if any, is the controller's to
        see at ``end``; the robot is closing anyway). Called from the step's own thread
        (a step that closes the robot at the run's end), it has nothing to wait for."""
        thread = self._thread
        if thread is not None and thread is not threading.current_thread():
            thread.join()
            sys.setswitchinterval(self._saved_interval)
        self._nursery.close()
