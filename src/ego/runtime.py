"""How a controller run is set up when the controller itself cannot say: ``ego run`` fills it.

A Webots controller constructs ``Robot()`` with no arguments; the port, a time limit and
progress listeners therefore come from here (set by ``ego run`` / ``ego demo``), or from
``EGO_PORT``.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from ego.robot import Robot

__all__ = ["RunOptions", "current", "set_options"]


@dataclass
class RunOptions:
    #: Where to connect (None: EGO_PORT, else /dev/ttyS0).
    port: str | None = None
    firmware: str | None = None
    #: After this much controller time, step() returns -1, as when Webots stops.
    duration_s: float | None = None
    #: What getBasicTimeStep() answers (ms); e-puck worlds commonly use 32.
    basic_time_step_ms: float = 32.0
    seed: int | None = None
    #: Called with each core Robot a face creates (progress displays subscribe here).
    on_robot: list[Callable[[Robot], None]] = field(default_factory=list)


_options = RunOptions()


def current() -> RunOptions:
    return _options


def set_options(options: RunOptions) -> None:
    global _options
    _options = options
