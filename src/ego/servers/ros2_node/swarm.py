"""N emulated robots in one world, each a ROS 2 node of its own in one graph.

``ego swarm --ros2``: the swarm's shared world (the emulator's crowd, through its backend:
ego never imports the emulator), each robot ``epuck_driver`` in the namespace
``/epuck<K>`` (its topics ``/epuck0/ps0``, ``/epuck0/cmd_vel``...), all on one Zenoh
session connected to the ROS machine's router, each stepped by its own
:class:`~ego.servers.ros2_node.runner.NodeRunner`. :meth:`RosSwarm.close` joins every
runner, stops every robot and withdraws every token.
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from contextlib import ExitStack
from typing import TYPE_CHECKING, Any

from ego.core.registry import find_backend
from ego.seam.profile import Firmware

if TYPE_CHECKING:
    from ego.core.robot import Robot
    from ego.servers.ros2_node.bridge import Ros2Bridge
    from ego.servers.ros2_node.runner import NodeRunner

__all__ = ["RosSwarm"]

log = logging.getLogger(__name__)


class RosSwarm:
    """``count`` emulated robots as ROS 2 nodes under ``/epuck0`` .. (see the module)."""

    def __init__(
        self, count: int, session: Any, *, world: str | None = None, firmware: str = "webots",
        seeds: list[int | None], distro: str = "jazzy", domain_id: int = 0,
        period_ms: int = 64, deadline_s: float = 0.5, name: Callable[[int], str] = "epuck{}".format,
    ) -> None:  # fmt: skip
        self.count, self.session, self.world, self.firmware = count, session, world, firmware
        self.seeds, self.distro, self.domain_id = seeds, distro, domain_id
        self.period_ms, self.deadline_s, self.name = period_ms, deadline_s, name
        self.robots: list[Robot] = []
        self.bridges: list[Ros2Bridge] = []
        self.runners: list[NodeRunner] = []
        self._stack = ExitStack()

    def start(self) -> RosSwarm:
        from ego.core.robot import Robot
        from ego.ros2.participant import Participant
        from ego.servers.ros2_node.bridge import Ros2Bridge
        from ego.servers.ros2_node.runner import NodeRunner

        backend: Any = find_backend("sim")
        worlds = backend.swarm_worlds(self.world, self.seeds)
        try:
            for index, world in enumerate(worlds):
                robot = Robot("sim", firmware=Firmware(self.firmware), world=world)
                self._stack.callback(robot.close)
                node = Participant(self.session, "epuck_driver", namespace=f"/{self.name(index)}",
                                   domain_id=self.domain_id, distro=self.distro)  # fmt: skip
                self._stack.callback(node.close)
                bridge = Ros2Bridge(robot, node, period_ms=self.period_ms,
                                    deadline_s=self.deadline_s).attach()  # fmt: skip
                self._stack.callback(bridge.close)
                runner = NodeRunner(robot, self.period_ms, self.name(index))
                self._stack.callback(runner.close)
                self.robots.append(robot)
                self.bridges.append(bridge)
                self.runners.append(runner)
            for runner in self.runners:
                runner.start()
        except BaseException:
            self.close()
            raise
        return self

    def close(self) -> None:
        """Join every runner, then stop every robot and withdraw its node; again: nothing."""
        self._stack.close()
        self.robots, self.bridges, self.runners = [], [], []

    def __enter__(self) -> RosSwarm:
        return self.start()

    def __exit__(self, *exc: object) -> None:
        self.close()
