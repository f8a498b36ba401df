"""Fixtures for the face tests: the emulated dsPIC, the faces' default robot pointed at it,
and ``ego`` run as a subprocess. Every robot must have stopped its motors and switched its
LEDs off by the end of the test."""

from __future__ import annotations

import os
import subprocess
from collections.abc import Callable, Iterator
from pathlib import Path

import pytest
from helpers import assert_stopped, ego_command

from ego.controller import Robot as WebotsRobot
from ego.faces import default_robot, runtime
from firmware_sim import Emulator, World

#: One seed for every emulator here, so that a failure replays with the same sensor noise.
SEED = 11


@pytest.fixture
def emulator() -> Iterator[Emulator]:
    """The thesis firmware's dsPIC behind a pty, outliving the robots so their stop is seen."""
    with Emulator("webots", seed=SEED) as emu:
        yield emu


@pytest.fixture
def face_options(emulator: Emulator) -> Iterator[runtime.RunOptions]:
    """Point ``Robot()``, ``wb_robot_init()`` and ``overo_serial_init()`` at the emulator.

    ``ego run`` does the same through :func:`ego.faces.default_robot.set_options`; afterwards the
    default robot is closed and must have stopped the robot.
    """
    options = runtime.RunOptions(port=emulator.path)
    default_robot.set_options(options)
    try:
        yield options
    finally:
        default_robot.close()
        default_robot.set_options(runtime.RunOptions())
    assert_stopped(emulator.world)


@pytest.fixture
def webots_robot(face_options: runtime.RunOptions) -> Iterator[WebotsRobot]:
    """A Webots-API ``Robot()`` on the emulator, as a controller constructs it."""
    robot = WebotsRobot()
    try:
        yield robot
    finally:
        robot.cleanup()


@pytest.fixture
def check_stopped() -> Callable[[World], None]:
    """:func:`assert_stopped` for the tests."""
    return assert_stopped


@pytest.fixture
def run_ego(tmp_path: Path) -> Callable[..., subprocess.CompletedProcess[str]]:
    """Run ``ego ARGS...`` in a scratch directory (never inside src/ego) and capture it."""

    def run(
        *args: str, env: dict[str, str] | None = None, timeout_s: float = 30.0
    ) -> subprocess.CompletedProcess[str]:
        return subprocess.run(
            [*ego_command(), *args],
            cwd=tmp_path,
            env={**os.environ, **(env or {})},
            capture_output=True,
            text=True,
            timeout=timeout_s,
            check=False,
        )

    return run
