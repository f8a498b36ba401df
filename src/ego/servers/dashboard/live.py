"""The dashboard of a robot being driven: its samples out, the pages' commands in.

:class:`RobotDashboard` is what ``ego run --dashboard``, ``ego serve --dashboard`` and
``ego demo`` start: it serves the first robot the run opens, samples it after every step
(:mod:`ego.core.telemetry`), and lets the page that holds control act on it through a
:class:`~ego.servers.dashboard.control.ControlDesk` step guard. Without a dashboard none of this
exists: a robot's step runs no listener and no guard.
"""

from __future__ import annotations

import logging
import sys
from typing import TYPE_CHECKING, Any, TextIO

from ego.core.telemetry import Telemetry, describe_robot, describe_world
from ego.servers.dashboard.control import ControlDesk, KeySink, Reply
from ego.servers.dashboard.server import DashboardServer

if TYPE_CHECKING:
    from ego.core.robot import Robot

__all__ = ["RobotDashboard", "RobotFeed", "parse_address"]

log = logging.getLogger(__name__)

DEFAULT_PORT = 8765


def parse_address(text: str | None) -> tuple[str, int]:
    """``HOST:PORT``, ``[V6]:PORT``, ``HOST`` or a bare ``PORT`` (None: 127.0.0.1:8765)."""
    host, port = "127.0.0.1", str(DEFAULT_PORT)
    if text and text.startswith("["):
        host, _, rest = text[1:].partition("]")
        port = rest.removeprefix(":") or port
    elif text and text.count(":") == 1:
        host, port = text.split(":")
        host = host or "127.0.0.1"
    elif text and text.isdigit():
        port = text
    elif text:
        host = text
    if not port.isdigit() or int(port) > 65535 or not host:
        raise ValueError(f"dashboard address {text!r} is not HOST:PORT (port 0..65535)")
    return host, int(port)


class RobotFeed:
    """One robot as the dashboard sees it (a :class:`~ego.servers.dashboard.server.Feed`)."""

    def __init__(self, robot: Robot, key_sink: KeySink | None = None) -> None:
        self.robot = robot
        self.telemetry = Telemetry(robot)
        self.desk = ControlDesk(key_sink)
        self.server: DashboardServer | None = None
        self._frames = -1
        self._hello = {"mode": "live", "robot": describe_robot(robot),
                       "world": describe_world(robot.ground_truth),
                       "webots": bool(getattr(key_sink, "webots_face", False))}  # fmt: skip

    def hello(self) -> dict[str, Any]:
        return self._hello

    def state(self, client: object) -> dict[str, Any]:
        return self.desk.state(client)

    def handle(self, client: object, message: object) -> Reply:
        return self.desk.handle(client, message)

    def leave(self, client: object) -> None:
        self.desk.leave(client)

    def stop_now(self) -> None:
        self.robot.send_stop()

    def on_step(self, robot: Robot) -> None:
        """After each step: hand the newest sample and frame to the pages, when they would
        be sent (25 and 10 a second at most); otherwise only follow the odometry."""
        server = self.server
        if server is None or not server.wants_sample():
            self.telemetry.track()
        else:
            sample = self.telemetry.sample()
            self.desk.period_ms = max(1, round(sample["step_ms"] or 64))
            server.publish(sample)
        camera = robot.open_camera
        if server is None or camera is None or not camera.sampling_period:
            return
        if camera.frame_count != self._frames and server.wants_image():
            self._frames = camera.frame_count
            server.publish_frame(camera.image.copy())


class RobotDashboard:
    """Serves the first robot a run opens (``attach`` is a RunOptions.on_robot callback)."""

    def __init__(
        self,
        address: str | None = None,
        secret: bytes | None = None,
        key_sink: KeySink | None = None,
        out: TextIO = sys.stderr,
    ) -> None:
        self.host, self.port = parse_address(address)
        self.secret = secret
        self.key_sink = key_sink
        self.out = out
        self.feed: RobotFeed | None = None
        self.server: DashboardServer | None = None

    def attach(self, robot: Robot) -> None:
        if self.feed is not None:
            return  # one robot a dashboard
        feed = RobotFeed(robot, self.key_sink)
        try:
            server = DashboardServer(feed, self.host, self.port, self.secret).start()
        except OSError as exc:  # the usual port is taken (another ego): any free one
            if self.port != DEFAULT_PORT:
                raise
            log.info("port %d is taken (%s): the dashboard takes a free one", self.port, exc)
            server = DashboardServer(feed, self.host, 0, self.secret).start()
        feed.server = server
        self.feed, self.server = feed, server
        robot.add_step_guard(feed.desk.guard)
        robot.add_step_listener(feed.on_step)
        robot.add_closer(self.close)  # the robot's close ends the server's thread
        self.out.write(f"ego: dashboard at {server.url}\n")
        self.out.flush()

    def close(self) -> None:
        if self.server is not None:
            self.server.close()
        if self.feed is not None:
            self.feed.robot.remove_step_hooks(self.feed.desk.guard)
            self.feed.robot.remove_step_hooks(self.feed.on_step)
