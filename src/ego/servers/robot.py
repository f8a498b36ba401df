"""The robot a server serves: opened on a port (any backend's, through the registry) with
its camera, and closed as one."""

from __future__ import annotations

import logging
import os
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from ego.camera.v4l2 import DEFAULT_CAMERA_DEVICE
from ego.core.closing import close_each
from ego.core.environment import Environment, read_environment
from ego.core.ports import resolve_port
from ego.core.registry import open_port, takes_option
from ego.seam.channel import Channel
from ego.seam.profile import Firmware

if TYPE_CHECKING:
    from ego.camera.source import FrameSource
    from ego.core.ground_truth import GroundTruth

__all__ = ["ServedRobot", "open_robot"]

log = logging.getLogger(__name__)


@dataclass
class ServedRobot:
    """What ``ego serve`` opened: the channel, the camera, and how to close them all."""

    channel: Channel
    camera: FrameSource | None = None
    closers: list[Callable[[], None]] = field(default_factory=list)
    #: What the simulator behind a simulated robot knows of it (its world), else None.
    world: GroundTruth | None = None
    #: The robot's name in a failure's log line: its port.
    name: str = "robot"

    def close(self) -> None:
        close_each(self.name, self.closers, log)


def open_robot(
    port: str | None,
    firmware: str = "auto",
    camera: str | None = None,
    secret: bytes | None = None,
    environment: Environment | None = None,
    robot_kind: str | None = None,
) -> ServedRobot:
    """The robot on ``port`` (any backend's: "sim" starts an emulator) and its camera;
    ``secret`` goes to a backend that takes one (a robot served elsewhere),
    ``robot_kind`` ("epuck", "epuck2") to one that takes ``robot`` (the emulator's, a Pi-puck's).
    ``environment`` None: this process's (EGO_PORT, EGO_CAMERA...), read now."""
    environment = environment or read_environment()
    resolved = resolve_port(port, environment.port)
    # Only a device named on the command line goes to the backend (the emulator has no
    # V4L2 devices, and says so when given one).
    options: dict[str, Any] = {"camera_device": camera} if camera not in (None, "none") else {}
    if secret is not None and takes_option(resolved, "secret"):
        options["secret"] = secret
    if robot_kind is not None and takes_option(resolved, "robot"):
        options["robot"] = robot_kind
    opened = open_port(
        resolved, environment=environment, firmware=Firmware.choose(firmware), **options
    )
    robot = ServedRobot(
        opened.channel, closers=[opened.close], world=opened.ground_truth, name=resolved
    )
    device = camera or environment.camera
    # Serve the backend's camera: a simulated one always, a V4L2 device when named or
    # present (a robot without its camera board serves none rather than fail).
    wanted = opened.ground_truth is not None or device is not None
    present = wanted or os.path.exists(DEFAULT_CAMERA_DEVICE)
    if device != "none" and opened.camera is not None and present:
        robot.camera = opened.camera()
        robot.closers.insert(0, robot.camera.close)
    return robot


