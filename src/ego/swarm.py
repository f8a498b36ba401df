"""``ego swarm --robots N [--world FILE] controller.py``: N emulated e-pucks in one world.

The robots share one emulated world (each sees the others on its proximity sensors and
bumps into them: the emulator's crowd, reached through its backend, since ego never
imports the emulator). Each is served as a Zenoh node, ``epuck0`` .. ``epuckN-1``, on
this process's Zenoh session; each runs its controller in a process of its own through
``ego run --port zenoh://epuckK``: the same path as a real robot's. Webots' Emitter and
Receiver work between them (their signal strength from the world). Given several
controller files, robot K runs file ``K mod len(files)``.
"""

from __future__ import annotations

import contextlib
import os
import subprocess
import sys
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

from ego.backends import Opened, find_backend
from ego.serial.protocol import Firmware

__all__ = ["Swarm", "robot_name"]

#: The names of a swarm's robots: epuck0, epuck1...
NAME_PREFIX = "epuck"


def robot_name(index: int) -> str:
    return f"{NAME_PREFIX}{index}"


@dataclass
class Swarm:
    """N emulated robots in one world, served as Zenoh nodes (see the module's doc)."""

    count: int
    world: str | None = None
    firmware: str = "webots"
    seed: int | None = 1
    endpoint: str = "tcp/127.0.0.1:7447"
    deadline_s: float = 0.5
    worlds: list[Any] = field(default_factory=list)
    opened: list[Opened] = field(default_factory=list)
    nodes: list[Any] = field(default_factory=list)
    session: Any = None
    _closers: list[Any] = field(default_factory=list)

    def __post_init__(self) -> None:
        if not 1 <= self.count <= 64:
            raise ValueError(f"a swarm of {self.count} robots: 1..64 are served")

    def start(self) -> Swarm:
        from ego.zenoh_net.node import RobotNode
        from ego.zenoh_net.sessions import ZenohSettings, open_session

        backend: Any = find_backend("sim")
        self.worlds = backend.swarm_worlds(self.world, self.count, self.seed)
        self.session = open_session(ZenohSettings(listen=[self.endpoint], connect=[]))
        try:
            for index, world in enumerate(self.worlds):
                opened = backend.open("sim", firmware=Firmware(self.firmware), world=world)
                self.opened.append(opened)
                node = RobotNode(opened.channel, self.session, robot_name(index),
                                 deadline_s=self.deadline_s, world=world)  # fmt: skip
                self.nodes.append(node.start())
        except BaseException:
            self.close()
            raise
        return self

    def serve_dashboard(self, address: str | None, secret: bytes | None = None) -> str:
        """A dashboard of the whole swarm (every robot on the map, one stop for all); its URL."""
        from ego.dashboard.live import parse_address
        from ego.dashboard.served import SwarmFeed
        from ego.dashboard.server import DashboardServer

        feed = SwarmFeed([robot_name(i) for i in range(self.count)],
                         [node.watched for node in self.nodes])  # fmt: skip
        host, port = parse_address(address)
        server = DashboardServer(feed, host, port, secret).start()
        feed.server = server
        feed.start()
        self._closers.append(server.close)
        self._closers.append(feed.close)
        return server.url

    def close(self) -> None:
        while self._closers:
            self._closers.pop()()
        for node in self.nodes:
            node.close()
        for opened in self.opened:
            with contextlib.suppress(Exception):
                opened.close()
        if self.session is not None:
            self.session.close()
        self.nodes, self.opened, self.session = [], [], None

    def __enter__(self) -> Swarm:
        return self.start()

    def __exit__(self, *exc: object) -> None:
        self.close()

    def controller_env(self) -> dict[str, str]:
        """The environment a controller process reaches its robot with."""
        return {**os.environ, "EGO_ZENOH_CONNECT": self.endpoint,
                "EGO_ZENOH_LISTEN": "tcp/127.0.0.1:0"}  # fmt: skip

    def run_controllers(
        self, files: Sequence[str], args: Sequence[str] = (), duration_s: float | None = None
    ) -> list[int]:
        """Run each robot's controller in its own process until all end; their statuses."""
        processes = []
        for index in range(self.count):
            command = [sys.executable, "-m", "ego", "run", "--port",
                       f"zenoh://{robot_name(index)}"]  # fmt: skip
            if duration_s is not None:
                command += ["--duration", str(duration_s)]
            command += [files[index % len(files)], *args]
            processes.append(subprocess.Popen(command, env=self.controller_env()))
        try:
            return [process.wait() for process in processes]
        finally:
            for process in processes:
                if process.poll() is None:
                    process.terminate()
            deadline = time.monotonic() + 5
            for process in processes:
                with contextlib.suppress(subprocess.TimeoutExpired):
                    process.wait(max(0.1, deadline - time.monotonic()))
