"""Issue 33, "done when": Webots controllers run unchanged under ``ego run --port pipuck``
against the emulated Pi-puck (its shim in the child's environment): a published-style
e-puck2 controller (tof, gyro, RGB LEDs, ground sensors), the avoidance demo, and an
e-puck1 controller on York's register map."""

from __future__ import annotations

import json
import math
import os
import subprocess
from collections.abc import Callable
from pathlib import Path

import pytest
from helpers import ego_command, wait_until
from pipuck_support import CONTROLLERS, EXAMPLES, Runner

from firmware_sim.pipuck import PipuckEmulator


def test_a_published_e_puck2_controller_runs_unchanged(
    pipuck: Callable[..., PipuckEmulator], runner: Callable[[PipuckEmulator], Runner],
    tmp_path: Path,
) -> None:  # fmt: skip
    emu = pipuck()
    run = runner(emu)
    result = tmp_path / "seen.json"
    child = run.start_ego("run", "--port", "pipuck", "--duration", "3",
                          str(CONTROLLERS / "epuck2_published.py"), str(result))  # fmt: skip
    # Green while cruising, as 0..100 % of each RGB LED, and the red LED1 on.
    assert wait_until(lambda: emu.truth.rgb_leds == ((0, 100, 0),) * 4, 30), emu.truth
    assert emu.truth.red_leds[0]
    _, err = child.communicate(timeout=60)
    assert child.returncode == 0, err
    seen = json.loads(result.read_text())
    assert len(seen["tof"]) > 10 and all(19.8 <= v <= 2000 for v in seen["tof"])
    assert all(len(g) == 3 and all(v > 0 for v in g) for g in seen["ground"])
    assert all(abs(v - 9.81) < 1.0 for v in seen["acc_z"])  # the MPU-9250's z, 1 g
    assert seen["max_velocity"] == 7.536
    assert set(seen["colours"]) <= {0x00FF00, 0xFF0000}
    truth = emu.truth
    assert truth.last_was_stop and truth.checksum_errors == 0
    assert len(truth.sounds) == seen["played"]


def test_the_avoidance_demo_runs_unchanged_on_the_e_puck2(
    pipuck: Callable[..., PipuckEmulator], runner: Callable[[PipuckEmulator], Runner],
) -> None:  # fmt: skip
    emu = pipuck()
    start = emu.world.snapshot()
    done = runner(emu).ego("run", "--port", "pipuck", "--duration", "3",
                           str(EXAMPLES / "obstacle_avoidance.py"))  # fmt: skip
    assert done.returncode == 0, done.stderr
    moved = emu.world.snapshot()
    assert math.hypot(moved.x_m - start.x_m, moved.y_m - start.y_m) > 0.05
    assert emu.truth.last_was_stop


def test_an_e_puck1_controller_runs_on_yorks_register_map(
    pipuck: Callable[..., PipuckEmulator], runner: Callable[[PipuckEmulator], Runner],
    tmp_path: Path,
) -> None:  # fmt: skip
    emu = pipuck("epuck")
    run = runner(emu)
    result = tmp_path / "seen.json"
    child = run.start_ego("run", "--port", "pipuck", "--duration", "3",
                          str(CONTROLLERS / "epuck1_york.py"), str(result))  # fmt: skip
    # Detected from its LSM330; the body LED (register 1, bit 1) on, the IR measuring.
    assert wait_until(lambda: emu.truth.body_led and emu.truth.speeds != (0, 0), 30), emu.truth
    assert emu.truth.ir_enabled
    _, err = child.communicate(timeout=60)
    assert child.returncode == 0, err
    seen = json.loads(result.read_text())
    assert seen["steps"] > 10 and all(len(ps) == 8 for ps in seen["ps"])
    assert seen["left_rad"][-1] > seen["left_rad"][0]  # the left wheel turned forwards
    assert emu.truth.last_was_stop


def test_a_device_the_path_cannot_serve_is_refused_naming_the_one_that_can(
    pipuck: Callable[..., PipuckEmulator], runner: Callable[[PipuckEmulator], Runner],
) -> None:  # fmt: skip
    emu = pipuck()
    seen = runner(emu).script(
        "robot = ego.Robot('pipuck', camera_device='none')\n"
        "try:\n"
        "    robot.magnetometer.enable(32)\n"
        "finally:\n"
        "    robot.close()\n"
    )
    assert seen["error"] == "UnsupportedDeviceError"
    assert "epuck2-i2c" in seen["message"]
    york = pipuck("epuck")
    seen = runner(york).script(
        "robot = ego.Robot('pipuck', camera_device='none')\n"
        "try:\n"
        "    robot.microphones.enable(32)\n"
        "finally:\n"
        "    robot.close()\n"
    )
    assert seen["error"] == "UnsupportedDeviceError" and "york" in seen["message"]


@pytest.mark.parametrize("robot", ["epuck2", "epuck"])
def test_ego_demo_runs_on_an_emulated_pipuck(robot: str) -> None:
    done = subprocess.run([*ego_command(), "demo", "--pipuck", "--robot", robot,
                           "--duration", "2", "--no-dashboard"],
                          capture_output=True, text=True, timeout=120)  # fmt: skip
    assert done.returncode == 0, done.stderr
    assert f"emulated {robot} on a Pi-puck" in done.stdout
    assert "motors stopped" in done.stdout


def test_ego_demo_on_a_board_without_a_compiler_says_so_in_one_line(tmp_path: Path) -> None:
    """The emulated Pi-puck's shim is compiled on first use; a board installed as its
    guide says has no gcc (tools/board_check.sh found a traceback there)."""
    env = {**os.environ, "PATH": str(tmp_path)}  # an empty folder: no gcc on the path
    done = subprocess.run([*ego_command(), "demo", "--pipuck", "--duration", "1",
                           "--no-dashboard"],
                          capture_output=True, text=True, timeout=120, env=env)  # fmt: skip
    assert done.returncode == 1, done.stdout + done.stderr
    assert "Traceback" not in done.stderr, done.stderr
    assert done.stderr.strip().splitlines() == [
        "ego: error: the emulated Pi-puck cannot start: no C compiler (gcc) to build the I2C "
        "shim (it is compiled on first use: install gcc, or try the demo on a PC)"
    ]


def test_a_pipuck_run_is_recorded_and_replayed_like_any_other(
    pipuck: Callable[..., PipuckEmulator], runner: Callable[[PipuckEmulator], Runner],
    tmp_path: Path,
) -> None:  # fmt: skip
    emu = pipuck()
    run = runner(emu)
    first, second = tmp_path / "first.json", tmp_path / "second.json"
    controller = str(CONTROLLERS / "epuck2_published.py")
    done = run.ego("run", "--port", "pipuck", "--duration", "1", "--record", "run.mcap",
                   controller, str(first))  # fmt: skip
    assert done.returncode == 0, done.stderr
    replayed = subprocess.run(
        [*ego_command(), "replay", "--emulate", "--speed", "4", str(tmp_path / "run.mcap"),
         controller, str(second)],
        capture_output=True, text=True, timeout=120, cwd=tmp_path,
    )  # fmt: skip
    assert replayed.returncode == 0, replayed.stderr
    recorded, again = json.loads(first.read_text()), json.loads(second.read_text())
    assert again["tof"] == recorded["tof"] and again["ground"] == recorded["ground"]
