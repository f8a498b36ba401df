"""The cmd_vel deadman's own thread: it stops the wheels when cmd_vel falls silent, on time
whatever the steps do.

The thread waits on :meth:`Commands.next_lapse <ego.servers.ros2_node.commands.Commands.
next_lapse>` (a timer with a known deadline, not a poll), then sends the confirmed wheel
stop over the robot's channel at once (``D 0 0`` then ``E``, under the channel's lock:
between two steps' batches, as the dashboard's stop goes), rather than wait for a step
that a flood, a slow link or a busy machine can delay. ego's view of the wheels follows
at the next step (the guard takes the stop), and a step whose guard applied a Twist
before the lapse but whose batch went after the stop is followed at once by another
stop (:meth:`Deadman.after_step`). Each bridge has its own deadman, so one robot's flood
never holds another's. :class:`Deadman` owns the thread in a :class:`~ego.nursery.Nursery`:
its close ends and joins it, and a program that exits with the bridge still open has it
ended before Python waits for its threads (the nursery's ``at_exit``).
"""

from __future__ import annotations

import logging
import time
from collections.abc import Callable
from typing import TYPE_CHECKING

from ego.core.safety import STOP_ATTEMPTS, stop_requests
from ego.errors import EgoError, ProtocolError, RobotResetError
from ego.nursery import Nursery
from ego.serial.protocol import encode_batch

if TYPE_CHECKING:
    from ego.core.robot import Robot
    from ego.servers.ros2_node.commands import Commands

__all__ = ["Deadman", "stop_wheels"]

log = logging.getLogger(__name__)


def stop_wheels(robot: Robot) -> None:
    """Send ``D 0 0`` and ``E`` until the dsPIC confirms (0, 0), from any thread, between
    two steps' batches; the LEDs are left as they are. ProtocolError if never confirmed."""
    channel = robot.channel
    with channel.lock:
        for _ in range(STOP_ATTEMPTS):
            batch = encode_batch(stop_requests(()), channel.profile)
            try:
                held = batch.decode(channel.exchange(batch))[-1]
            except RobotResetError:
                continue  # a restarted dsPIC stands still; confirm anyway
            if tuple(held) == (0, 0):
                return
    raise ProtocolError("the robot did not confirm that its wheels stopped")


class Deadman:
    """Stops ``robot``'s wheels whenever ``commands``' deadman lapses (see the module)."""

    def __init__(self, robot: Robot, commands: Commands, *, name: str,
                 clock: Callable[[], float] = time.monotonic) -> None:  # fmt: skip
        self.robot, self.commands = robot, commands
        self._clock = clock
        self._name = f"ego-ros2-deadman {name}"
        self._nursery = Nursery(self._name, at_exit=commands.close)
        self._started = False
        #: When the wheels were last confirmed stopped by the deadman (``clock``).
        self.stopped_at: float | None = None
        self.stops = 0
        self._seen_lapses = 0

    def start(self) -> Deadman:
        if not self._started:
            self._nursery.start_thread(self._run, name=self._name)
            self._started = True
        return self

    def _run(self) -> None:
        while (lapsed := self.commands.next_lapse()) is not None:
            log.info("cmd_vel %s: robot stopped", lapsed.why)
            self._stop()

    def _stop(self) -> None:
        try:
            stop_wheels(self.robot)
        except (EgoError, OSError) as exc:  # the next step sends D 0 0 again
            log.error("%s: the deadman could not stop the wheels: %s", self.robot.port, exc)
            return
        self.stopped_at = self._clock()
        self.stops += 1

    def before_step(self, lapses: int) -> None:
        """The step's guard took the commands when the deadman had lapsed ``lapses``
        times: lapses from then on are after it."""
        self._seen_lapses = lapses

    def after_step(self) -> None:
        """If the deadman lapsed while this step ran, its batch may have carried a Twist
        the guard applied before the lapse, after the deadman's stop: stop again now."""
        if self.commands.lapses != self._seen_lapses:
            self._stop()

    def close(self) -> None:
        """End the thread and join it (ThreadLeakError if it outlives the nursery's
        deadline); again does nothing."""
        self.commands.close()
        self._nursery.close()
