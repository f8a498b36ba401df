"""A robot on the emulator, stepped by a controller function in a thread and served by a
real dashboard on loopback."""

from __future__ import annotations

import os
import queue
import re
import threading
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import IO, Any

import ego
from ego.nursery import Nursery
from ego.servers.dashboard.live import RobotDashboard
from tests.helpers import world_of

#: An empty walled arena: the robot starts facing the east wall, 25 cm from it.
OPEN_WORLD = """
box = []
[arena]
size_m = 1.0
[robot]
x_m = 0.2
y_m = 0.0
heading_deg = 0
"""


@dataclass
class Served:
    robot: ego.Robot
    url: str
    dashboard: RobotDashboard

    @property
    def world(self) -> Any:
        return world_of(self.robot)


@contextmanager
def served_robot(
    tmp_path: Path,
    controller: Callable[[ego.Robot], None],
    world: str = OPEN_WORLD,
    address: str = "127.0.0.1:0",
    secret: bytes | None = None,
) -> Iterator[Served]:
    """A robot stepping every 32 ms with ``controller(robot)`` before each step, until the
    block ends; its dashboard at ``address``."""
    path = tmp_path / "world.toml"
    path.write_text(world)
    # The emulator answers from a thread of this process, beside Chromium's driver and
    # the dashboard: the sim backend's link allows for replies a busy host holds up.
    robot = ego.Robot("sim", world=str(path), seed=1)
    dashboard = RobotDashboard(address, secret, out=open(os.devnull, "w"))  # noqa: SIM115
    dashboard.attach(robot)
    stop = threading.Event()
    failures: list[BaseException] = []

    def loop() -> None:
        try:
            while not stop.is_set():
                controller(robot)
                if robot.step(32) == -1:
                    return
        except BaseException as exc:  # reported by the test
            failures.append(exc)

    threads = Nursery("the test's controller", join_s=10)
    threads.start_thread(loop, name="test-controller")
    try:
        assert dashboard.server is not None
        yield Served(robot, dashboard.server.url, dashboard)
    finally:
        stop.set()
        threads.close()
        dashboard.close()
        robot.close()
        dashboard.out.close()
    assert not failures, failures


class LineReader:
    """A child's output, drained line by line by a thread of its own (so that it never
    fills its pipe, and no line waits in a buffer that select cannot see). The thread
    ends with the stream (the child's exit): :meth:`rest` joins it."""

    def __init__(self, stream: IO[str]) -> None:
        self.lines: queue.Queue[str] = queue.Queue()
        self.threads = Nursery("a child's output")
        self.threads.start_thread(self._drain, stream, name="test-line-reader")

    def _drain(self, stream: IO[str]) -> None:
        for line in stream:
            self.lines.put(line)
        self.lines.put("")  # the end

    def find(self, pattern: str, timeout_s: float = 30) -> str:
        """The first group of ``pattern`` in the next lines."""
        seen = []
        end = time.monotonic() + timeout_s
        while (left := end - time.monotonic()) > 0:
            try:
                line = self.lines.get(timeout=left)
            except queue.Empty:
                break
            seen.append(line)
            match = re.search(pattern, line)
            if match:
                return match.group(1)
            if not line:
                break
        raise AssertionError(f"no {pattern!r} in {seen}")

    def close(self, timeout_s: float = 10) -> None:
        """Join the thread, once the child's exit has ended the stream."""
        self.threads.close(timeout_s)

    def rest(self, timeout_s: float = 10) -> str:
        """Every line not yet found, once the stream has ended."""
        self.close(timeout_s)
        lines = []
        while not self.lines.empty():
            lines.append(self.lines.get())
        return "".join(lines)
