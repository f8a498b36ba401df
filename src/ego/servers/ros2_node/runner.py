"""The thread that steps robots bridged to ROS 2: one owner that starts, stops and joins it.

Nothing else drives a robot the bridge serves in ``ego ros2`` and ``ego swarm --ros2``:
the runner steps its robot every ``period_ms`` (the robot's own pacer keeps the time),
in one thread named ``ego-ros2 <name>``, until :meth:`NodeRunner.close` (which joins
it) or until the robot's link is lost (:attr:`NodeRunner.ended` is then set).
"""

from __future__ import annotations

import logging
import threading
from types import TracebackType
from typing import TYPE_CHECKING

from ego.nursery import Nursery

if TYPE_CHECKING:
    from ego.core.robot import Robot

__all__ = ["NodeRunner"]

log = logging.getLogger(__name__)


class NodeRunner:
    """Steps ``robot`` in a thread of its own (see the module's doc)."""

    def __init__(self, robot: Robot, period_ms: int, name: str) -> None:
        self.robot = robot
        self.period_ms = period_ms
        self._name = name
        self._stop = threading.Event()
        # A program that exits with the runner open: the loop ends first (no daemon).
        self._threads = Nursery(f"the ROS 2 runner of {name}", at_exit=self._stop.set)
        #: Set when the thread ended (closed, the robot's link lost, or an error).
        self.ended = threading.Event()
        #: What ended the thread, if an error did (the owner raises it on).
        self.error: BaseException | None = None

    def start(self) -> NodeRunner:
        self._threads.start_thread(self._run, name=f"ego-ros2 {self._name}")
        return self

    def _run(self) -> None:
        try:
            while not self._stop.is_set():
                if self.robot.step(self.period_ms) == -1:
                    log.error("%s: link lost, no longer bridged", self.robot.port)
                    return
        except Exception as exc:  # kept for the owner, which raises it in its thread
            log.error("%s: bridging stopped: %s", self.robot.port, exc)
            self.error = exc
        finally:
            self.ended.set()

    def close(self) -> None:
        """Stop stepping and join the thread (ThreadLeakError if it will not end); again
        does nothing."""
        self._stop.set()
        self._threads.close()

    def __enter__(self) -> NodeRunner:
        return self.start()

    def __exit__(
        self, exc_type: type[BaseException] | None, exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:  # fmt: skip
        self.close()
