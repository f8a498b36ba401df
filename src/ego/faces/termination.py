"""A controller ends the way Webots ends it.

Webots' user guide ("Controller Termination"): once ``step()`` has returned -1 (the
simulation is quitting, reverting or the controller is being changed), the controller
has about one second of real time to clean up and return; then Webots kills it. A
controller whose loop ignores -1 (``while True: robot.step(32)``) therefore ends a
second later in Webots, and must here too, or it spins on for ever calling a step that
does nothing (a Q-learning loop ran 80,000 empty episodes in 100 s before this).

Every face's step goes through :meth:`Termination.ended` when it returns -1: the first
-1 starts the grace (on ``time.monotonic``, the clock it is measured on); any step
after :data:`GRACE_S` raises :class:`~ego.errors.ControllerTerminated`, which ``ego
run`` reports in one line and exits with :data:`TERMINATED_STATUS`. The robot was
stopped and closed when the first -1 was returned.
"""

from __future__ import annotations

import time
from collections.abc import Callable

from ego.errors import ControllerTerminated

__all__ = ["GRACE_S", "TERMINATED_STATUS", "Termination"]

#: Real time (s) a controller has after its first -1 (Webots: "about one second").
GRACE_S = 1.0
#: ``ego run``'s exit status for a controller ended this way (as ``timeout(1)``'s).
TERMINATED_STATUS = 124


class Termination:
    """When a run's step first returned -1, and why; the end of the controller's grace."""

    def __init__(self, clock: Callable[[], float] = time.monotonic) -> None:
        self._clock = clock
        #: When step() first returned -1 (``clock``'s seconds), None before.
        self.ended_at: float | None = None
        self.why = ""

    def ended(self, why: str) -> int:
        """-1, the step's answer once the run is over; the first call starts the grace,
        a call after it raises ControllerTerminated saying why the run ended."""
        now = self._clock()
        if self.ended_at is None:
            self.ended_at, self.why = now, why
        elif now - self.ended_at >= GRACE_S:
            raise ControllerTerminated(
                f"the controller was ended {now - self.ended_at:.1f} s after step() "
                f"returned -1 ({self.why}), as Webots ends a controller that goes on",
                TERMINATED_STATUS,
            )
        return -1
