"""How a controller run is set up when the controller itself cannot say: ``ego run`` fills it.

A Webots controller constructs ``Robot()`` with no arguments; the port, a time limit and
progress listeners therefore come from the run's :class:`RunOptions` (made by ``ego run``
/ ``ego demo``, held by the current :class:`ego.faces.default_robot.FaceContext`), or from
``EGO_PORT``. This module is data only: the run's context (which options are current, the
robot the faces opened) is :mod:`ego.faces.default_robot`'s.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from ego.core.robot import Robot

__all__ = ["RunOptions"]


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
    #: ``ego run --world``: the emulator's world (a built-in name or a TOML file; port sim).
    world: str | None = None
    #: ``ego run --robot``: which robot the emulator models, "epuck" or "epuck2" (port sim).
    robot: str | None = None
    #: ``ego run --strict``: where Webots would print a warning and carry on (an unknown
    #: device, a speed beyond the maximum), the Webots face raises ego's error instead.
    strict: bool = False
    #: ``ego run --camera WxH``: the Webots face's camera size (None: Webots' e-puck 52x39).
    camera_size: tuple[int, int] | None = None
    #: ``ego run --fast``: the emulator in virtual time, as fast as it can (port sim).
    fast: bool = False
    #: ``ego run --secret-file``: the shared secret of a served robot (tcp://, udp://, unix://).
    secret: bytes | None = None
    #: Called with each core Robot a face creates (progress displays subscribe here).
    on_robot: list[Callable[[Robot], None]] = field(default_factory=list)

    def robot_options(self) -> dict[str, object]:
        """The options the faces open their robot with: those this run sets (one left
        None is not set, and goes to no backend: each port's backend takes its own)."""
        given = {
            "firmware": self.firmware,
            "seed": self.seed,
            "world": self.world,
            "robot": self.robot,
            "virtual_time": True if self.fast else None,
            "secret": self.secret,
        }
        return {name: value for name, value in given.items() if value is not None}

    def time_is_up(self, time_s: float) -> bool:
        """Whether a controller at ``time_s`` of controller time has used up ``duration_s``.

        The one cutoff of ``ego run --duration``: the Webots ``Robot.step`` and the
        C-style faces' step both end the run (returning -1) once this is true.
        """
        return self.duration_s is not None and time_s >= self.duration_s - 1e-9

    def time_up_reason(self) -> str:
        """Why a step returned -1 once :meth:`time_is_up`, in words."""
        if self.duration_s is None:
            return "the run's time was up"
        return f"the run's --duration of {self.duration_s:g} s was up"

