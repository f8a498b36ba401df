"""What watches a run beside its controller: the dashboard and the recorder.

Both attach to the first robot the run opens (a RunOptions.on_robot callback) and are
closed when the run ends, whichever way it ends. Neither exists unless asked for: a run
without them adds no listener and no guard to its robot's step.
"""

from __future__ import annotations

import contextlib
import sys
from typing import TYPE_CHECKING, TextIO

if TYPE_CHECKING:
    from ego.core.robot import Robot
    from ego.faces.runtime import RunOptions

__all__ = ["observe_run"]


def observe_run(
    options: RunOptions,
    *,
    dashboard: str | None = None,
    secret_file: str | None = None,
    record: str | None = None,
    record_ros2: str | None = None,
    out: TextIO = sys.stderr,
) -> contextlib.ExitStack:
    """Attach a dashboard at ``dashboard`` (``HOST:PORT``; None: none) and a recorder to
    ``record`` (an .mcap path; None: none) to the run of ``options``; close them on exit.
    ``record_ros2``: the recording is a ROS 2 bag of that distribution (``jazzy``)."""
    stack = contextlib.ExitStack()
    if record is not None:
        from ego.recording.writer import Recorder

        recorder = Recorder(record, ros2_distro=record_ros2)
        stack.callback(recorder.close)
        options.on_robot.append(recorder.attach)
    if dashboard is not None:
        from ego.controller.keyboard import FaceKeys
        from ego.faces.default_robot import current_context
        from ego.net.auth import load_secret
        from ego.servers.dashboard.live import RobotDashboard

        secret = load_secret(secret_file) if secret_file else None
        board = RobotDashboard(dashboard, secret, out=out)
        stack.callback(board.close)

        def attach(robot: Robot) -> None:
            # Called inside the run's face context: the keys go to its Webots Keyboard.
            board.key_sink = FaceKeys(current_context())
            board.attach(robot)

        options.on_robot.append(attach)
    return stack
