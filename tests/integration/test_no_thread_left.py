"""Every thread has an owner that stops and joins it: closing a Robot leaves none behind.

A simulated robot with its camera capturing, a recording and a live dashboard starts
threads of its own (the emulator's, the recorder's writer, the dashboard's server); the
Robot's close ends and joins each of them, whoever else holds the recorder or dashboard.
"""

from __future__ import annotations

import io
import threading
from pathlib import Path

import ego
from ego.faces.runtime import RunOptions
from ego.recording.writer import Recorder
from ego.servers.dashboard.live import RobotDashboard


def _others(before: set[threading.Thread]) -> list[str]:
    return sorted(t.name for t in threading.enumerate() if t not in before and t.is_alive())


def test_closing_a_robot_with_camera_recording_and_dashboard_leaves_no_thread(
    tmp_path: Path,
) -> None:
    before = set(threading.enumerate())
    recorder = Recorder(tmp_path / "run.mcap")
    board = RobotDashboard("127.0.0.1:0", out=io.StringIO())
    robot = ego.Robot("sim", seed=2)
    recorder.attach(robot)
    board.attach(robot)
    robot.camera.enable(64)
    robot.proximity.enable(64)
    for _ in range(4):
        assert robot.step(64) == 0
    assert _others(before)  # the run had threads of its own
    robot.close()
    assert _others(before) == []
    recorder.close()  # their owners' own close stays harmless after the robot's
    board.close()
    assert (tmp_path / "run.mcap").stat().st_size > 0


def test_the_keyboards_reader_ends_with_the_robot() -> None:
    """A Webots controller's keyboard reads its terminal (here a pty) on a thread of its
    own; the core robot's close, however the run ends it, stops and joins that thread."""
    import os
    import pty

    from ego.controller import Keyboard, Robot

    before = set(threading.enumerate())
    leader, follower = pty.openpty()
    robot = Robot(options=RunOptions(port="sim", seed=1))
    try:
        robot.keyboard = Keyboard(16, fd=follower)
        assert robot.step(16) == 0
        assert "ego-keyboard" in _others(before)
        robot.core.close()  # what ego run does at the end of the run
        assert _others(before) == []
    finally:
        robot.cleanup()
        os.close(leader)
        os.close(follower)
