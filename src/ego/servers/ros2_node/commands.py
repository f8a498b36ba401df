"""What ROS 2 asks of the robot, held between steps: cmd_vel, the LEDs, the deadman (no I/O).

Messages arrive on Zenoh's threads whenever they come; the bridge applies what they ask
at the start of the next step (a step guard), so the robot is only ever driven from its
own step. The deadman is :class:`~ego.servers.sessions.control.ControlSession`'s, the
one both of ego's servers run: each Twist is the holder ``cmd_vel`` being heard, and a
holder silent past ``deadline_s`` lapses, which stops the wheels, as ROS drivers stop a
robot whose ``cmd_vel`` went quiet. Time is handed in.
"""

from __future__ import annotations

import threading
from dataclasses import dataclass, field

from ego.servers.sessions.control import ControlSession, Lapsed

__all__ = ["Commands", "Pending"]

#: The deadman's one holder: whoever publishes on cmd_vel.
CMD_VEL = "cmd_vel"


@dataclass
class Pending:
    """What the next step must apply: wheel speeds (steps/s), LEDs (index: on)."""

    speeds: tuple[int, int] | None = None
    leds: dict[int, int] = field(default_factory=dict)
    stop: Lapsed[str] | None = None


class Commands:
    """Commands from ROS 2 waiting for the next step, and the cmd_vel deadman."""

    def __init__(self, deadline_s: float) -> None:
        self.control = ControlSession[str](deadline_s)
        self._pending = Pending()
        self._lock = threading.Lock()

    def drive(self, speeds: tuple[int, int], now: float) -> None:
        """A Twist came: these speeds, and the deadman waits anew."""
        with self._lock:
            self.control.take(CMD_VEL, now)
            self._pending.speeds = speeds

    def led(self, index: int, on: bool) -> None:
        with self._lock:
            self._pending.leds[index] = int(on)

    def take(self, now: float) -> Pending:
        """What the step starting ``now`` applies; ``stop`` set when the deadman lapsed
        (speeds then None: the stop wins over a Twist older than the deadline)."""
        with self._lock:
            pending, self._pending = self._pending, Pending()
            lapsed = self.control.tick(now)
            if lapsed is not None:
                pending.stop, pending.speeds = lapsed, None
            return pending
