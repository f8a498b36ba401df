"""Webots controllers run unchanged through ``ego run`` and ``run_controller`` (issue 3, item 4).

Each controller file in ``controllers/`` is written as a Webots user writes it and reports
what it saw as JSON; it runs once as an ``ego run --port sim`` subprocess and once
in-process on an emulator whose world the test can inspect.
"""

from __future__ import annotations

import json
import math
import subprocess
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

import ego.controller
from ego.app.runner import run_controller
from ego.faces import default_robot, runtime
from firmware_sim import Emulator, World

CONTROLLERS = Path(__file__).parent / "controllers"
Result = dict[str, Any]


def finite(values: list[float]) -> bool:
    return bool(values) and all(isinstance(v, (int, float)) and math.isfinite(v) for v in values)


def check_getdevice(result: Result, duration_s: float) -> None:
    # from controller import Robot, Motor, DistanceSensor: ego's classes.
    assert result["classes"] == [
        "ego.controller.robot",
        "ego.controller.motor",
        "ego.controller.distance_sensor",
    ]
    assert result["types_match"]
    assert math.isnan(result["not_yet_sampled"])  # Webots gives NaN before the first sample
    assert finite(result["proximity"]) and len(result["proximity"]) == 8
    assert finite(result["light"]) and len(result["light"]) == 8
    assert finite(result["floor"]) and len(result["floor"]) == 3
    assert result["accelerometer"][2] == pytest.approx(9.81, abs=0.5)
    # Spinning in place: left wheel forward, right wheel backward (a negative velocity).
    (left0, right0), (left, right) = result["wheels_start"], result["wheels"]
    travelled = 3.0 * (duration_s - 0.1)
    assert left - left0 > 0.5 * travelled
    assert right0 - right > 0.5 * travelled
    assert result["velocities"] == [3.0, -3.0]
    assert result["time"] == pytest.approx(duration_s, abs=0.04)
    assert result["steps"] == pytest.approx(duration_s / 0.032, abs=1)
    assert result["basic_time_step"] == 32.0
    assert result["sampling_period"] == 32
    assert result["name"] == "e-puck"
    assert result["mode"] == ego.controller.Robot.MODE_CROSS_COMPILATION
    assert result["led"] == 1


def check_deprecated_getters(result: Result, duration_s: float) -> None:
    assert result["types"] == [
        "DistanceSensor",
        "LightSensor",
        "Accelerometer",
        "PositionSensor",
        "Camera",
        "LED",
        "Motor",
    ]
    assert finite(result["proximity"]) and finite(result["light"])
    assert finite(result["accelerometer"])
    assert result["left_wheel"] - result["left_wheel_start"] > 0.5 * 2.0 * (duration_s - 0.1)
    assert result["leds"] == [1] * 10


def check_differential_wheels(result: Result, duration_s: float) -> None:
    assert math.isnan(result["not_yet_sampled"])
    assert result["first"][0] == pytest.approx(1000, abs=15)  # setEncoders, read back at once
    assert result["first"][1] == pytest.approx(-1000, abs=15)
    assert result["last"][0] - result["first"][0] > 0.5 * 300 * (duration_s - 0.1)
    assert result["first"][1] - result["last"][1] > 0.5 * 200 * (duration_s - 0.1)
    assert math.isfinite(result["proximity"])
    assert result["speeds"] == [300.0, -200.0]
    assert result["max_speed"] == 1000.0
    assert result["speed_unit"] == pytest.approx(0.00628)
    assert result["encoders_period"] == 32


CHECKS: dict[str, Callable[[Result, float], None]] = {
    "getdevice_controller.py": check_getdevice,
    "deprecated_getters_controller.py": check_deprecated_getters,
    "differential_wheels_controller.py": check_differential_wheels,
}


@pytest.mark.parametrize("controller", sorted(CHECKS))
def test_a_webots_controller_runs_unchanged_under_ego_run(
    controller: str,
    run_ego: Callable[..., subprocess.CompletedProcess[str]],
    tmp_path: Path,
) -> None:
    result_path = tmp_path / "result.json"
    done = run_ego(
        "run",
        "--port",
        "sim",
        "--duration",
        "0.5",
        "--seed",
        "3",
        str(CONTROLLERS / controller),
        str(result_path),  # the controller's own argv[1]
    )
    assert done.returncode == 0, done.stderr
    CHECKS[controller](json.loads(result_path.read_text()), 0.5)


@pytest.mark.parametrize("controller", sorted(CHECKS))
def test_a_webots_controller_runs_unchanged_in_process(
    controller: str,
    emulator: Emulator,
    world: World,
    tmp_path: Path,
    check_stopped: Callable[[World], None],
) -> None:
    result_path = tmp_path / "result.json"
    options = runtime.RunOptions(port=emulator.path, duration_s=0.5)
    run_controller(CONTROLLERS / controller, options, [str(result_path)])
    CHECKS[controller](json.loads(result_path.read_text()), 0.5)
    check_stopped(world)


def test_run_controller_makes_the_controller_module_ego_and_then_restores_it(
    emulator: Emulator, tmp_path: Path
) -> None:
    sentinel = object()
    sys.modules["controller"] = sentinel  # type: ignore[assignment]
    path_before = sys.path[:]
    try:
        run_controller(
            CONTROLLERS / "getdevice_controller.py",
            runtime.RunOptions(port=emulator.path, duration_s=0.1),
            [str(tmp_path / "result.json")],
        )
        assert sys.modules["controller"] is sentinel
    finally:
        sys.modules.pop("controller", None)
    assert sys.path == path_before
    assert default_robot.current_options().port is None  # the run's options do not outlive it
    result = json.loads((tmp_path / "result.json").read_text())
    assert result["classes"][0] == "ego.controller.robot"


def test_position_control_turns_the_wheel_one_turn(
    emulator: Emulator, tmp_path: Path, check_stopped: Callable[[World], None]
) -> None:
    result_path = tmp_path / "result.json"
    options = runtime.RunOptions(port=emulator.path, duration_s=4.0)
    run_controller(CONTROLLERS / "position_controller.py", options, [str(result_path)])
    result = json.loads(result_path.read_text())

    assert result["settled"], result
    steps = result["angle"] * 1000 / (2 * math.pi)
    assert steps == pytest.approx(1000, rel=0.03)
    assert result["time"] > 2 * math.pi / 3.0  # it went no faster than setVelocity(3)
    check_stopped(emulator.world)


@pytest.mark.parametrize("controller", ["webots_c_controller.py", "overo_controller.py"])
def test_a_c_style_controller_ends_when_ego_runs_duration_is_up(
    controller: str,
    emulator: Emulator,
    tmp_path: Path,
    check_stopped: Callable[[World], None],
) -> None:
    result_path = tmp_path / "result.json"
    options = runtime.RunOptions(port=emulator.path, duration_s=0.5)
    run_controller(CONTROLLERS / controller, options, [str(result_path)])
    result = json.loads(result_path.read_text())

    assert result["steps"] == pytest.approx(0.5 / 0.032, abs=1)
    assert result["left_encoder"] > 50
    assert math.isfinite(result.get("ps0", result.get("ps7")))
    check_stopped(emulator.world)
