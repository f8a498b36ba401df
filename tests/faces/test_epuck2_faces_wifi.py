"""The same published-style Webots e-puck2 controller and the avoidance demo, unchanged,
under ``ego run --port epuck2://HOST:PORT``: the e-puck2's radio (its emulator's WiFi
server on loopback) instead of its USB pty. What they read comes through the WiFi stream
and the e-puck2 profile's families, as over USB."""

from __future__ import annotations

import json
import math
import subprocess
from collections.abc import Callable, Iterator
from pathlib import Path

import pytest
from test_epuck2_faces import CONTROLLERS, EXAMPLES, _check_tof_gyro

from firmware_sim.epuck2 import Epuck2Emulator


@pytest.fixture
def radio() -> Iterator[Epuck2Emulator]:
    with Epuck2Emulator("arena", seed=4, wifi=True, port=0) as emulator:
        yield emulator
    assert emulator.world.speeds == (0, 0), "the e-puck2 was left running"


@pytest.fixture
def url(radio: Epuck2Emulator) -> str:
    assert radio.wifi_address is not None
    host, port = radio.wifi_address
    return f"epuck2://{host}:{port}"


def test_a_published_e_puck2_controller_runs_unchanged_over_wifi(
    url: str, run_ego: Callable[..., subprocess.CompletedProcess[str]], tmp_path: Path
) -> None:
    result = tmp_path / "result.json"
    done = run_ego("run", "--port", url, "--duration", "3",
                   str(CONTROLLERS / "epuck2_tof_gyro.py"), str(result), timeout_s=60)  # fmt: skip
    assert done.returncode == 0, done.stderr
    _check_tof_gyro(json.loads(result.read_text()))


def test_the_avoidance_demo_runs_unchanged_over_wifi(
    url: str, radio: Epuck2Emulator, run_ego: Callable[..., subprocess.CompletedProcess[str]]
) -> None:
    start = radio.world.snapshot()
    done = run_ego("run", "--port", url, "--duration", "3",
                   str(EXAMPLES / "obstacle_avoidance.py"), timeout_s=60)  # fmt: skip
    assert done.returncode == 0, done.stderr
    moved = radio.world.snapshot()
    assert math.hypot(moved.x_m - start.x_m, moved.y_m - start.y_m) > 0.1
    assert radio.world.closest_approach_m > 0.0
