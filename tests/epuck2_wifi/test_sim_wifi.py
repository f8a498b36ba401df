"""The emulator's WiFi mode behind ego: ``Robot("sim", robot="epuck2", wifi=True)``, and the
URL ``python -m firmware_sim --robot epuck2 --wifi`` prints, opened as ``epuck2://``."""

from __future__ import annotations

import subprocess
import sys

import pytest
from helpers import wait_until

import ego
from ego.errors import BackendOptionError


def test_the_sim_backend_s_wifi_mode_drives_the_emulated_e_puck2() -> None:
    with ego.Robot("sim", robot="epuck2", wifi=True, seed=4) as robot:
        assert robot.channel.name.startswith("epuck2://127.0.0.1:")
        assert robot.channel.info.selector == 15
        truth = robot.ground_truth
        assert truth is not None
        start = truth.pose()
        robot.motors.set_speed(500, 500)
        robot.proximity.enable(32)
        for _ in range(10):
            robot.step(32)
        assert wait_until(lambda: (truth.pose().x_m, truth.pose().y_m) != (start.x_m, start.y_m))


def test_wifi_is_the_e_puck2_s() -> None:
    with pytest.raises(BackendOptionError, match="wifi=True is the e-puck2's"):
        ego.Robot("sim", robot="epuck", wifi=True)


def test_the_url_the_emulator_prints_opens_as_epuck2() -> None:
    emulator = subprocess.Popen(
        [sys.executable, "-m", "firmware_sim", "--robot", "epuck2", "--wifi", "--wifi-port", "0"],
        stdout=subprocess.PIPE,
        text=True,
    )
    try:
        assert emulator.stdout is not None
        printed = emulator.stdout.readline().strip()
        assert printed.startswith("tcp://127.0.0.1:")
        url = "epuck2://" + printed.removeprefix("tcp://")
        with ego.Robot(url) as robot:
            robot.proximity.enable(32)
            robot.step(32)
            assert len(robot.proximity.values) == 8
    finally:
        emulator.terminate()
        emulator.wait(10)
