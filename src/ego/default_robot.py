"""The one robot that the C-style faces (``ego.webots``, ``ego.overo``) act on."""

from __future__ import annotations

from ego import runtime
from ego.errors import EgoError
from ego.robot import Robot
from ego.serial.protocol import DEFAULT_BAUD

__all__ = ["close", "get", "is_open", "open_robot", "step"]

_robot: Robot | None = None


def open_robot(port: str | None = None, baudrate: int | None = None) -> Robot:
    """Open the default robot (closing a previous one); ``port`` None: ``ego run``'s or EGO_PORT."""
    global _robot
    close()
    options = runtime.current()
    _robot = Robot(
        port or options.port,
        firmware=options.firmware,
        seed=options.seed,
        baudrate=baudrate or DEFAULT_BAUD,
    )
    for callback in options.on_robot:
        callback(_robot)
    return _robot


def get() -> Robot:
    if _robot is None:
        raise EgoError("no robot is open: call wb_robot_init() or overo_serial_init() first")
    return _robot


def step(ms: int) -> int:
    """One time step of the default robot; -1 once ``ego run --duration`` is used up (then closed).

    Both C-style faces step through here, so that a time limit ends an E-GO controller's
    ``overo_scheduler_robot_step`` loop as it ends a Webots one's ``wb_robot_step`` loop.
    """
    robot = get()
    limit = runtime.current().duration_s
    if limit is not None and robot.time_s >= limit - 1e-9:
        close()
        return -1
    return robot.step(ms)


def is_open() -> bool:
    return _robot is not None


def close() -> None:
    global _robot
    if _robot is not None:
        _robot.close()
        _robot = None
