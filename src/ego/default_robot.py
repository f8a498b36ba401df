"""The one robot that the C-style faces (``ego.webots``, ``ego.overo``) act on."""

from __future__ import annotations

from ego import runtime
from ego.errors import EgoError
from ego.robot import Robot
from ego.serial.protocol import DEFAULT_BAUD

__all__ = ["close", "get", "is_open", "open_robot"]

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


def is_open() -> bool:
    return _robot is not None


def close() -> None:
    global _robot
    if _robot is not None:
        _robot.close()
        _robot = None
