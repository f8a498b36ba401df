"""The scene a Supervisor sees in the emulated world: the robot and the named boxes, their
poses and velocities, moved by hand and put back as the world began (Webots'
``simulationReset``). Written from Webots' Supervisor API, apart from ego."""

from __future__ import annotations

from dataclasses import dataclass, replace

from firmware_sim.markers import Marker
from firmware_sim.world import Pose, World

__all__ = ["ROBOT", "Scene"]

#: The name that stands for the robot itself (``getSelf``), whatever its DEF name.
ROBOT = ""


@dataclass(frozen=True)
class _Start:
    robot: Pose
    blocks: tuple[tuple[float, float, float], ...]
    markers: tuple[Marker, ...]


class Scene:
    """The world's solids by name: ``ROBOT`` for the robot, a box's DEF name for a box.
    Poses and velocities are answered in the world file's own frame (its arena where it
    stands, its NUE numbers if it speaks NUE: firmware_sim.frame), as Webots answers."""

    def __init__(self, world: World) -> None:
        self.world = world
        self._start = _Start(
            world.snapshot(),
            tuple((b.x_m, b.y_m, b.yaw_rad) for b in world.blocks),
            tuple(world.markers),
        )

    @property
    def robot_name(self) -> str | None:
        """The robot's DEF name in the world file, if it has one."""
        return self.world.robot_name

    def names(self) -> tuple[str, ...]:
        """Every DEF name the scene answers to (the robot's first, if it has one)."""
        robot = (self.world.robot_name,) if self.world.robot_name else ()
        markers = (m.name for m in self.world.markers)
        return (*robot, *(b.name for b in self.world.blocks if b.name), *markers)

    def kind(self, name: str) -> str:
        """The Webots node type behind ``name``: ``E-puck``, ``Solid``, or a marker's own."""
        if self._is_robot(name):
            return "E-puck"
        marker = self._marker(name)
        return "Solid" if marker is None else self.world.markers[marker].kind

    @property
    def vertical(self) -> tuple[float, float, float]:
        """The world's up axis in the file's numbers: (0, 0, 1), or (0, 1, 0) for NUE."""
        return self.world.frame.vertical

    def pose(self, name: str) -> tuple[float, float, float, float]:
        """x, y, z (m) and the angle of the turn about :attr:`vertical` (rad) of the solid
        ``name``, in the world file's frame."""
        return self.world.frame.to_file(*self._own_pose(name))

    def _own_pose(self, name: str) -> tuple[float, float, float, float]:
        """x, y, z (m) and yaw (rad) in the emulator's frame (the arena's)."""
        if self._is_robot(name):
            p = self.world.snapshot()
            return p.x_m, p.y_m, 0.0, p.theta_rad
        marker = self._marker(name)
        if marker is not None:
            m = self.world.markers[marker]
            return m.x_m, m.y_m, m.z_m, m.yaw_rad
        block = self.world.blocks[self._block(name)]
        return block.x_m, block.y_m, block.height_m / 2, block.yaw_rad

    def set_pose(self, name: str, position: tuple[float, float, float], angle_rad: float) -> None:
        """Put the solid ``name`` at ``position``, turned ``angle_rad`` about the vertical,
        both in the world file's frame (kept out of the walls; z is the floor's)."""
        x_m, y_m, _, yaw_rad = self.world.frame.from_file(position, angle_rad)
        marker = self._marker(name)
        if self._is_robot(name):
            self.world.place(Pose(x_m, y_m, yaw_rad))
        elif marker is not None:
            markers = self.world.markers
            markers[marker] = replace(markers[marker], x_m=x_m, y_m=y_m, yaw_rad=yaw_rad)
        else:
            self.world.move_block(self._block(name), x_m, y_m, yaw_rad)

    def velocity(self, name: str) -> tuple[float, float, float, float, float, float]:
        """Linear (m/s) and angular (rad/s) velocity, world frame; boxes stand still."""
        if not self._is_robot(name):
            if self._marker(name) is None:
                self._block(name)
            return (0.0,) * 6
        return self.world.frame.velocity_to_file(*self.world.velocity())

    def reset(self, stop: bool = True) -> None:
        """Everything back where the world began, the robot standing still (Webots'
        motors stop at a reset); the controller's robot then stops its wheels and zeroes
        its counters over the wire, as the dsPIC takes them. Without ``stop`` the wheels
        keep their speeds (a swarm's other robots: their controllers are not told)."""
        if stop:
            self.world.set_speeds(0, 0)
        self.world.place(self._start.robot)
        for index, (x, y, yaw) in enumerate(self._start.blocks):
            self.world.move_block(index, x, y, yaw)
        self.world.markers[:] = self._start.markers

    def _is_robot(self, name: str) -> bool:
        return name == ROBOT or name == self.world.robot_name

    def _marker(self, name: str) -> int | None:
        for index, marker in enumerate(self.world.markers):
            if marker.name == name:
                return index
        return None

    def _block(self, name: str) -> int:
        for index, block in enumerate(self.world.blocks):
            if block.name == name:
                return index
        raise KeyError(f"no solid named {name!r} in the world; named: {', '.join(self.names())}")
