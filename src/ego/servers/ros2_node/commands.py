"""What ROS 2 asks of the robot, held between steps: cmd_vel, the LEDs, the deadman (no I/O).

Messages arrive on the subscriptions' threads whenever they come; the bridge applies
what they ask at the start of the next step (a step guard). The deadman is
:class:`~ego.servers.sessions.control.ControlSession`'s, the one both of ego's servers
run: each Twist is the holder ``cmd_vel`` being heard, and a holder silent past
``deadline_s`` lapses, which stops the wheels, as ROS drivers stop a robot whose
``cmd_vel`` went quiet. :meth:`Commands.next_lapse` waits for that moment on its own
(a timer with a known deadline, woken by each Twist), so the bridge's deadman thread
(:mod:`ego.servers.ros2_node.deadman`) stops the wheels then, whenever the next step
comes. Time comes from ``clock`` (monotonic seconds).
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
from dataclasses import dataclass, field

from ego.servers.sessions.control import ControlSession, Lapsed

__all__ = ["Commands", "Pending"]

#: The deadman's one holder: whoever publishes on cmd_vel.
CMD_VEL = "cmd_vel"
#: Past the deadline by this much when the deadman looks (tick wants "more than").
_JUST_PAST_S = 1e-4


@dataclass
class Pending:
    """What the next step must apply: wheel speeds (steps/s), LEDs (index: on), and the
    deadman's stop (the wheels were stopped since the last step: ego's view follows)."""

    speeds: tuple[int, int] | None = None
    leds: dict[int, int] = field(default_factory=dict)
    stop: Lapsed[str] | None = None
    #: How many times the deadman had lapsed when the step took these.
    lapses: int = 0


class Commands:
    """Commands from ROS 2 waiting for the next step, and the cmd_vel deadman."""

    def __init__(self, deadline_s: float, clock: Callable[[], float] = time.monotonic) -> None:
        self.control = ControlSession[str](deadline_s)
        self._clock = clock
        self._pending = Pending()
        self._wake = threading.Condition()
        self._closed = False
        #: When the last Twist was heard, and when the deadman last lapsed (``clock``).
        self.heard_at: float | None = None
        self.lapsed_at: float | None = None

    def drive(self, speeds: tuple[int, int]) -> None:
        """A Twist came: these speeds, and the deadman waits anew."""
        with self._wake:
            now = self._clock()
            idle = self.control.holder is None
            self.control.take(CMD_VEL, now)
            self._pending.speeds = speeds
            self.heard_at = now
            if idle:  # the deadman waits without a deadline: it has one now. Otherwise it
                self._wake.notify_all()  # wakes at the old one and waits on (no wake a Twist)

    def led(self, index: int, on: bool) -> None:
        with self._wake:
            self._pending.leds[index] = int(on)

    def take(self) -> Pending:
        """What the step starting now applies (``stop`` set when the deadman lapsed since
        the last step; ``speeds`` then come from a Twist heard after it, if any)."""
        with self._wake:
            pending, self._pending = self._pending, Pending()
            pending.lapses = self.control.lapses
            return pending

    @property
    def lapses(self) -> int:
        with self._wake:
            return self.control.lapses

    def next_lapse(self) -> Lapsed[str] | None:
        """Wait until cmd_vel has been silent past the deadline and return the lapse (the
        Twist still waiting is dropped: older than the deadline); None once closed. Waits
        without a timeout while nobody drives, else until the deadline (a Twist moves it)."""
        with self._wake:
            while not self._closed:
                now = self._clock()
                lapsed = self.control.tick(now)
                if lapsed is not None:
                    self._pending.speeds, self._pending.stop = None, lapsed
                    self.lapsed_at = now
                    return lapsed
                due_s = self.control.due_in(now)
                self._wake.wait(None if due_s is None else max(due_s, 0.0) + _JUST_PAST_S)
            return None

    def close(self) -> None:
        """:meth:`next_lapse` returns None, now and from now on."""
        with self._wake:
            self._closed = True
            self._wake.notify_all()
