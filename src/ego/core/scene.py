"""What a simulated robot's world lets a Webots Supervisor see and move: a typed seam.

A real robot has no scene to supervise; the emulator (a backend ego never imports) hands
one in through :class:`~ego.backends.Opened`, as does the Zenoh backend for a swarm's
node that serves its world (ego.backends.zenoh_scene), and :attr:`ego.Robot.scene` is
it, else None. Solids are named as in the world file (a box's DEF name; ``""`` for the robot).
"""

from __future__ import annotations

from typing import Protocol

__all__ = ["ROBOT", "Scene"]

#: The name of the robot itself, whatever its DEF name in the world file.
ROBOT = ""


class Scene(Protocol):
    """The solids of a simulated world; an unknown name raises KeyError."""

    @property
    def robot_name(self) -> str | None:
        """The robot's DEF name in the world file, if it has one."""
        ...

    def names(self) -> tuple[str, ...]:
        """Every DEF name the scene answers to."""
        ...

    def kind(self, name: str) -> str:
        """The Webots node type behind ``name`` (``E-puck``, ``Solid``)."""
        ...

    @property
    def vertical(self) -> tuple[float, float, float]:
        """The world's up axis in the world file's numbers: (0, 0, 1) in Webots' ENU
        frame, (0, 1, 0) in a world declared NUE (x north, y up, z east)."""
        ...

    def pose(self, name: str) -> tuple[float, float, float, float]:
        """x, y, z (m) in the world file's frame, and the angle (rad) of the solid's turn
        about :attr:`vertical` (the floor is flat: no roll, no pitch)."""
        ...

    def set_pose(self, name: str, position: tuple[float, float, float], angle_rad: float) -> None:
        """Move the solid ``name`` to ``position`` (the world file's frame; its height is
        the floor's), turned ``angle_rad`` about :attr:`vertical`."""
        ...

    def velocity(self, name: str) -> tuple[float, float, float, float, float, float]:
        """Linear (m/s) and angular (rad/s) velocity in the world file's frame."""
        ...

    def reset(self) -> None:
        """Every solid back where the world began (Webots' ``simulationReset``)."""
        ...
