"""``ego swarm --robots N [--world FILE] controller.py``: N emulated e-pucks in one world.

The robots share one emulated world (each sees the others on its proximity sensors and
bumps into them: the emulator's crowd, reached through its backend, since ego never
imports the emulator). Each is served as a Zenoh node, ``epuck0`` .. ``epuckN-1``, on
this process's Zenoh session; each runs its controller in a process of its own through
``ego run --port zenoh://epuckK``: the same path as a real robot's. Webots' Emitter and
Receiver work between them (their signal strength from the world). Given several
controller files, robot K runs file ``K mod len(files)``.

Every robot's controller may be a Webots Supervisor of the swarm's world: its node
serves the world's scene (``ego/epuckK/scene``), where ``getFromDef`` reaches the other
robots by their DEF names (``epuckK`` where the world file gives none), the boxes and
the markers, and ``simulationReset`` puts them all back. A ``.wbt`` world's bodiless
supervisors (``Robot { supervisor TRUE controller "NAME" }``) run beside the robots:
each is served as a node of its own (its ``name`` field), its controller
``controllers/NAME/NAME.py`` beside the world's folder (Webots' layout) run as the
robots' are, its body in no robot's way (it carries the emulated e-puck's devices, of
which a Robot node uses its Emitter and Receiver).

Each robot's sensors have a noise stream of their own, seeded from the swarm's seed and
the robot's index (:func:`robot_seed`): the same seed gives the same run, and no two
robots read the same noise. What a controller prints reaches this process's standard
output and error line by line, each line headed by its robot's name (``[epuck0] ``).
"""

from __future__ import annotations

import logging
import os
import subprocess
import sys
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import IO, Any

from ego.core.backend import Opened
from ego.core.closing import close_each
from ego.core.registry import find_backend, open_port
from ego.errors import ThreadLeakError
from ego.nursery import Nursery
from ego.seam.profile import Firmware

__all__ = ["MAX_ROBOTS", "Swarm", "robot_name", "robot_seed"]

log = logging.getLogger(__name__)

#: The names of a swarm's robots: epuck0, epuck1...
NAME_PREFIX = "epuck"
#: The largest swarm served.
MAX_ROBOTS = 64


def robot_name(index: int) -> str:
    return f"{NAME_PREFIX}{index}"


def robot_seed(seed: int | None, index: int) -> int | None:
    """The noise seed of robot ``index`` in a swarm seeded ``seed`` (None: a fresh one).

    ``seed * MAX_ROBOTS + index``: distinct for every robot of every seed, so that two
    seeds never share a stream between their robots (``seed + index`` would give robot 1
    of seed 1 the noise of robot 0 of seed 2).
    """
    return None if seed is None else seed * MAX_ROBOTS + index


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
    #: Which robot the emulator models: "epuck" (None) or "epuck2" (its own firmware,
    #: whatever ``firmware`` says).
    robot: str | None = None
    #: The bodiless supervisors: each one's node name and controller file.
    supervisors: list[tuple[str, str]] = field(default_factory=list)

    def __post_init__(self) -> None:
        if not 1 <= self.count <= MAX_ROBOTS:
            raise ValueError(f"a swarm of {self.count} robots: 1..{MAX_ROBOTS} are served")

    def start(self) -> Swarm:
        from ego.core.environment import read_environment
        from ego.servers.zenoh_node.node import RobotNode
        from ego.zenoh_net.sessions import ZenohSettings, open_session

        backend: Any = find_backend("sim")
        seeds = [robot_seed(self.seed, index) for index in range(self.count)]
        self.worlds = backend.swarm_worlds(self.world, seeds)
        bodiless = backend.swarm_supervisors(self.world, self.worlds, self.seed)
        names = [robot_name(index) for index in range(self.count)]
        self.supervisors = []
        for k, (_, name, controller, _) in enumerate(bodiless):
            taken = [*names, *(n for n, _ in self.supervisors)]  # two unnamed: robot, robot
            self.supervisors.append(
                (_node_name(name, k, taken), _controller_file(self.world, controller))
            )
        members = [*self.worlds, *(world for *_, world in bodiless)]
        scene_names = [*names, *(def_name for def_name, *_ in bodiless)]
        scenes = backend.swarm_scenes(members, scene_names, len(bodiless))
        channels = backend.swarm_channels(self.world, self.worlds)
        node_names = [*names, *(name for name, _ in self.supervisors)]
        settings = ZenohSettings.from_environment(
            read_environment(), listen=[self.endpoint], connect=[]
        )  # the environment's EGO_ZENOH_CONFIG, if any
        self.session = open_session(settings)
        try:
            for index, world in enumerate(members):
                firmware = None if self.robot == "epuck2" else Firmware(self.firmware)
                opened = open_port("sim", firmware=firmware, world=world, robot=self.robot)
                self.opened.append(opened)
                node = RobotNode(opened.channel, self.session, node_names[index],
                                 deadline_s=self.deadline_s, world=opened.ground_truth,
                                 scene=scenes[index], radio=channels[index])  # fmt: skip
                self.nodes.append(node.start())
        except BaseException:
            self.close()
            raise
        return self

    def serve_dashboard(self, address: str | None, secret: bytes | None = None) -> str:
        """A dashboard of the whole swarm (every robot on the map, one stop for all); its URL."""
        from ego.servers.dashboard.live import parse_address
        from ego.servers.dashboard.served import SwarmFeed
        from ego.servers.dashboard.server import DashboardServer

        feed = SwarmFeed([robot_name(i) for i in range(self.count)],  # the robots, not a
                         [node.watched for node in self.nodes[: self.count]])  # supervisor's body
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
        for name, opened in zip(self.member_names, self.opened, strict=False):
            close_each(name, [opened.close], log)
        if self.session is not None:
            self.session.close()
        self.nodes, self.opened, self.session = [], [], None

    @property
    def member_names(self) -> list[str]:
        """The robots' node names, then the bodiless supervisors'."""
        return [*(robot_name(i) for i in range(self.count)), *(n for n, _ in self.supervisors)]

    def __enter__(self) -> Swarm:
        return self.start()

    def __exit__(self, *exc: object) -> None:
        self.close()

    def controller_env(self) -> dict[str, str]:
        """The environment a controller process reaches its robot with (its output
        unbuffered: its lines are relayed as they come)."""
        return {**os.environ, "EGO_ZENOH_CONNECT": self.endpoint,
                "EGO_ZENOH_LISTEN": "tcp/127.0.0.1:0", "PYTHONUNBUFFERED": "1"}  # fmt: skip

    def run_controllers(
        self, files: Sequence[str], args: Sequence[str] = (), duration_s: float | None = None
    ) -> list[int]:
        """Run each robot's controller, then each bodiless supervisor's, in its own process
        until all end; their statuses, in :attr:`member_names`' order.

        Their output is relayed line by line, each line headed ``[NAME] ``, by threads of
        a :class:`~ego.nursery.Nursery`: one still running 5 s after the processes ended (a
        controller's own child process holding its output open) is a ThreadLeakError.
        """
        processes: list[subprocess.Popen[bytes]] = []
        relays = Nursery("ego swarm's output relays")
        runs = [(robot_name(index), files[index % len(files)], list(args))
                for index in range(self.count)]  # fmt: skip
        runs += [(name, controller, []) for name, controller in self.supervisors]
        try:
            for name, file, arguments in runs:
                command = [sys.executable, "-m", "ego", "run", "--port", f"zenoh://{name}"]
                if duration_s is not None:
                    command += ["--duration", str(duration_s)]
                command += [file, *arguments]
                pipe = subprocess.PIPE
                process = subprocess.Popen(command, env=self.controller_env(), stdout=pipe,
                                           stderr=pipe)  # fmt: skip
                processes.append(process)
                _relay(relays, process, f"[{name}] ")
            return [process.wait() for process in processes]
        finally:
            _end_all(processes)  # their pipes close: the relays end
            try:
                relays.close()
            except ThreadLeakError as exc:
                raise ThreadLeakError(f"{exc} (a controller's own child process still holds "
                                      "its output open)") from exc  # fmt: skip


def _node_name(name: str, index: int, taken: Sequence[str]) -> str:
    """A bodiless supervisor's node name: its own where Zenoh takes it and no other
    member has it yet, else ``supervisorK``."""
    from ego.zenoh_net.keys import check_name

    try:
        check_name(name)
    except ValueError:
        return f"supervisor{index}"
    return name if name not in taken else f"supervisor{index}"


def _controller_file(world: str | None, controller: str) -> str:
    """Where Webots finds a world's controller NAME: ``controllers/NAME/NAME.py`` in the
    project whose ``worlds`` folder holds the world file."""
    from pathlib import Path

    from ego.errors import WorldFileError

    assert world is not None  # only a world file holds bodiless supervisors
    path = Path(world).resolve().parent.parent / "controllers" / controller / f"{controller}.py"
    if not path.is_file():
        raise WorldFileError(f"{world}: the supervisor's controller {controller!r} is not at "
                             f"{path} (Webots' layout: controllers/NAME/NAME.py)")  # fmt: skip
    return str(path)


def _relay(relays: Nursery, process: subprocess.Popen[bytes], prefix: str) -> None:
    """Threads of ``relays`` that copy ``process``'s output and errors here, each line
    after ``prefix``."""
    for source, to in ((process.stdout, sys.stdout), (process.stderr, sys.stderr)):
        if source is not None:
            relays.start_thread(_copy_lines, source, to, prefix,
                                name=f"ego-swarm-relay {prefix.strip()}")  # fmt: skip


def _copy_lines(source: IO[bytes], to: IO[str], prefix: str) -> None:
    with source:
        for raw in source:
            line = raw.decode("utf-8", "replace").rstrip("\r\n")
            to.write(f"{prefix}{line}\n")
            to.flush()


def _end_all(processes: Sequence[subprocess.Popen[bytes]]) -> None:
    """Terminate the processes still running, give each up to 5 s to end, then kill it:
    once all are gone their pipes close and the relays (not daemons) end and are joined."""
    for process in processes:
        if process.poll() is None:
            process.terminate()
    deadline = time.monotonic() + 5
    for process in processes:
        try:
            process.wait(max(0.1, deadline - time.monotonic()))
        except subprocess.TimeoutExpired:
            log.warning("%s did not end within 5 s of SIGTERM: killed", process.args)
            process.kill()
            process.wait()


def run_ros2(count: int, world: str | None, firmware: str, seed: int | None, router: list[str],
             distro: str, domain: int, duration_s: float | None) -> int:  # fmt: skip
    """``ego swarm --ros2``: the robots as ROS 2 nodes ``/epuckK/epuck_driver`` in one
    graph (ego.servers.ros2_node.swarm) until a signal or ``duration_s``."""
    import threading

    from ego.app.ros2 import wait_for_signal
    from ego.core.environment import read_environment
    from ego.servers.ros2_node.router import open_router_session
    from ego.servers.ros2_node.swarm import RosSwarm
    from ego.zenoh_net.sessions import ZenohSettings

    if not 1 <= count <= MAX_ROBOTS:
        raise ValueError(f"a swarm of {count} robots: 1..{MAX_ROBOTS} are served")
    settings = ZenohSettings.from_environment(read_environment(), listen=None, connect=router)
    # A client of the router, checked as ego ros2's (docs/ros2.md, "Who can drive").
    session: Any = open_router_session(settings.connect, settings.config_file)
    try:
        seeds = [robot_seed(seed, index) for index in range(count)]
        with RosSwarm(count, session, world=world, firmware=firmware, seeds=seeds,
                      distro=distro, domain_id=domain, name=robot_name):  # fmt: skip
            print(f"ego swarm: {count} emulated e-pucks as ROS 2 nodes "
                  f"/{robot_name(0)}..{robot_name(count - 1)}/epuck_driver ({distro}, domain "
                  f"{domain}) via {', '.join(settings.connect)}",
                  file=sys.stderr, flush=True)  # fmt: skip
            wait_for_signal(threading.Event(), duration_s)
    finally:
        session.close()
    return 0
