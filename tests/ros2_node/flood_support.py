"""What the ROS 2 flood tests measure: a teleop that falls silent and when the wheels
stopped after it, how late the robot's steps came, and how many log lines were written."""

from __future__ import annotations

import logging
import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

from helpers import wait_until
from zenoh.ext import Int64, z_serialize

from benchmarks.ros2_floods import twist_payload
from ego.core.robot import Robot
from ego.servers.ros2_node.convert import twist_to_steps
from firmware_sim.world import World, stepping_rate

TWIST = "geometry_msgs/msg/Twist"
#: The teleop's speed: 0.05 m/s, 388 steps/s on each wheel.
TELEOP_MPS = 0.05


class Teleop:
    """A ROS 2 teleop as rmw_zenoh publishes: Twists on ``key`` with the attachment."""

    def __init__(self, session: Any, key: str) -> None:
        self.publisher = session.declare_publisher(key)
        self.sequence = 0

    def matched(self) -> bool:
        return bool(self.publisher.matching_status.matching)

    def send(self, linear_x: float = TELEOP_MPS) -> None:
        self.sequence += 1
        attachment = z_serialize((Int64(self.sequence), Int64(time.time_ns()), bytes(16)))
        self.publisher.put(twist_payload(linear_x), attachment=attachment)

    def drive_for(self, robot: Robot, seconds: float) -> None:
        """Publish at 20 Hz for ``seconds``, as a teleop node does."""
        end = time.monotonic() + seconds
        while time.monotonic() < end:
            self.send()
            time.sleep(0.05)

    def close(self) -> None:
        self.publisher.undeclare()


def start_driving(teleop: Teleop, robot: Robot) -> None:
    want = twist_to_steps(TELEOP_MPS, 0.0)

    def driving() -> bool:
        teleop.send()
        return robot.motors.speed == want

    assert wait_until(lambda: teleop.matched(), 10)
    assert wait_until(driving, 10), robot.motors.speed


def silence_to_stop_s(teleop: Teleop, world: World) -> float:
    """The teleop's last Twist, then silence: seconds until the emulator's wheels stopped.
    The wheels' step counters stop with them, so how far they turned after a known
    moment dates the stop, however late this thread sees it (tests/zenoh does the same)."""
    speed = twist_to_steps(TELEOP_MPS, 0.0)[0]
    silent_since = time.monotonic()  # before the last Twist goes out: conservative
    teleop.send()
    assert world.speeds == (speed, speed), world.speeds
    counted = world.steps_int16()[0]
    counted_by = time.monotonic()  # after the reading: conservative
    assert wait_until(lambda: world.speeds == (0, 0), 5), "the deadman never stopped"
    turned = world.steps_int16()[0] - counted + 1  # +1: both readings are floored
    return counted_by + turned / stepping_rate(speed) - silent_since


class StepTimes:
    """When each step of ``robot`` ended (a step listener), from now until closed."""

    def __init__(self, robot: Robot) -> None:
        self.robot = robot
        self.times: list[float] = []
        self._lock = threading.Lock()
        robot.add_step_listener(self._record)

    def _record(self, _: Robot) -> None:
        with self._lock:
            self.times.append(time.monotonic())

    def latest_s(self, period_s: float) -> float:
        """How much later than ``period_s`` after the one before the latest step came."""
        with self._lock:
            gaps = [b - a for a, b in zip(self.times, self.times[1:], strict=False)]
        return max(gaps, default=0.0) - period_s

    def close(self) -> None:
        self.robot.remove_step_hooks(self._record)


class LogCount(logging.Handler):
    """Counts ego's log records of WARNING and above."""

    def __init__(self) -> None:
        super().__init__(logging.WARNING)
        self.lines: list[str] = []

    @property
    def count(self) -> int:
        return len(self.lines)

    def emit(self, record: logging.LogRecord) -> None:
        self.lines.append(f"{record.name}: {record.getMessage()}"[:300])


@contextmanager
def counted_logs() -> Iterator[LogCount]:
    handler = LogCount()
    logger = logging.getLogger("ego")
    logger.addHandler(handler)
    try:
        yield handler
    finally:
        logger.removeHandler(handler)
