"""The scene a Supervisor sees in a swarm: every robot by its name, the world's boxes and
markers, and the bodiless supervisors (firmware_sim.wbt_supervisor). Written from Webots'
Supervisor API, apart from ego.

Each robot of a swarm keeps a world of its own (firmware_sim.crowd), each with its copy
of the boxes: a box moved here moves in every world, so that all robots sense it where
the Supervisor put it. ``simulationReset`` puts every robot, box and marker back where
the world began (the asking member's robot standing still, the others keeping their
wheels' speeds: see :meth:`SwarmScene.reset`). A bodiless supervisor is a solid of the
scene (Webots' ``Robot`` node: its pose, no velocity) that no robot senses.
"""

from __future__ import annotations

from collections.abc import Sequence

from firmware_sim.scene import ROBOT, Scene
from firmware_sim.world import World

__all__ = ["SwarmScene"]


class SwarmScene:
    """The swarm's solids as seen from one of its members: ``me`` is the index in
    ``worlds`` whose robot ``ROBOT`` (``getSelf``) stands for. ``names`` are the members'
    names (their DEF names), one for each world; ``bodiless`` says how many of the last
    worlds are bodiless supervisors (Webots' type ``Robot``), not e-pucks."""

    def __init__(
        self, worlds: Sequence[World], names: Sequence[str], me: int, bodiless: int = 0
    ) -> None:
        if len(worlds) != len(names) or not 0 <= me < len(worlds) or bodiless > len(worlds):
            raise ValueError(f"{len(worlds)} worlds, {len(names)} names, member {me}")
        self.worlds = list(worlds)
        self.robots = list(names)
        self.me = me
        self._first_bodiless = len(worlds) - bodiless
        # Each world's own scene: its robot's and boxes' start, for the reset.
        self._scenes = [Scene(world) for world in self.worlds]

    @property
    def robot_name(self) -> str | None:
        return self.robots[self.me]

    def names(self) -> tuple[str, ...]:
        """The robots' names, then the boxes' and markers' DEF names."""
        return (*self.robots, *(n for n in self._scenes[0].names() if n not in self.robots))

    def _robot(self, name: str) -> int | None:
        if name == ROBOT:
            return self.me
        return self.robots.index(name) if name in self.robots else None

    def kind(self, name: str) -> str:
        index = self._robot(name)
        if index is None:
            return self._scenes[0].kind(name)
        return "Robot" if index >= self._first_bodiless else "E-puck"

    def pose(self, name: str) -> tuple[float, float, float, float]:
        index = self._robot(name)
        if index is None:
            return self._scenes[0].pose(name)
        return self._scenes[index].pose(ROBOT)

    @property
    def vertical(self) -> tuple[float, float, float]:
        return self._scenes[0].vertical

    def set_pose(self, name: str, position: tuple[float, float, float], angle_rad: float) -> None:
        """Move a robot in its own world, a box or a marker in every world (``position``
        in the world file's frame, ``angle_rad`` about its vertical)."""
        index = self._robot(name)
        if index is not None:
            self._scenes[index].set_pose(ROBOT, position, angle_rad)
            return
        for scene in self._scenes:
            scene.set_pose(name, position, angle_rad)

    def velocity(self, name: str) -> tuple[float, float, float, float, float, float]:
        index = self._robot(name)
        if index is None:
            return self._scenes[0].velocity(name)
        return self._scenes[index].velocity(ROBOT)

    def reset(self) -> None:
        """Every robot, box and marker back where the world began. The asking member's
        robot stands still (its controller then resets its motors, as Webots' reset
        does); the others keep the wheel speeds their controllers last set, which those
        controllers, in processes of their own, still believe in: stopping them would
        leave a robot still while its controller thinks it drives."""
        for index, scene in enumerate(self._scenes):
            scene.reset(stop=index == self.me)
