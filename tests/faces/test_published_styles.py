"""Controllers in the styles people publish for the e-puck, run unchanged by ``ego run`` on
the emulator; what each did is read from the emulator's world."""

from __future__ import annotations

import math
import select
import signal
import subprocess
from pathlib import Path
from typing import Any

import pytest
from helpers import ego_command

from ego.app.runner import run_controller
from ego.faces import runtime
from firmware_sim import Emulator
from tests.helpers import world_of

CONTROLLERS = Path(__file__).parent / "controllers"


def _run(emu: Emulator, name: str, tmp_path: Path) -> subprocess.Popen[str]:
    command = [*ego_command(), "run", "--port", emu.path, str(CONTROLLERS / name)]
    return subprocess.Popen(
        command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=tmp_path
    )


def test_an_odometry_script_estimates_the_pose_the_robot_really_took(tmp_path: Path) -> None:
    with Emulator("webots", seed=2) as emu:
        start = emu.world.snapshot()
        proc = _run(emu, "odometry.py", tmp_path)
        out, err = proc.communicate(timeout=30)
        assert proc.returncode == 0, err
        end = emu.world.snapshot()
    _, x, y, theta = out.split()[-4:] if out.split()[0] == "odometry" else ["", "", "", ""]
    # The world's displacement, in the robot's starting frame.
    dx, dy = end.x_m - start.x_m, end.y_m - start.y_m
    c, s = math.cos(-start.theta_rad), math.sin(-start.theta_rad)
    true_x, true_y = c * dx - s * dy, s * dx + c * dy
    true_theta = math.remainder(end.theta_rad - start.theta_rad, 2 * math.pi)
    assert abs(float(x) - true_x) < 0.01 and abs(float(y) - true_y) < 0.01, (x, y, true_x, true_y)
    assert abs(float(theta) - true_theta) < 0.1
    assert math.hypot(true_x, true_y) > 0.05  # it did drive


def test_a_model_branch_and_too_fast_velocities_run_clamped_with_webots_warning(
    tmp_path: Path,
) -> None:
    with Emulator("webots", seed=2) as emu:
        proc = _run(emu, "model_branch.py", tmp_path)
        try:
            assert proc.stdout is not None
            ready, _, _ = select.select([proc.stdout], [], [], 20)
            assert ready and proc.stdout.readline().strip() == "model GCtronic e-puck"
            ready, _, _ = select.select([proc.stdout], [], [], 20)
            assert ready and proc.stdout.readline().strip() == "running"
            assert emu.world.speeds == (1000, -1000)  # clamped to the maximum, not refused
        finally:
            proc.send_signal(signal.SIGTERM)
            _, err = proc.communicate(timeout=15)
        assert "The requested velocity 12.56 exceeds 'maxVelocity' = 6.28319." in err
        assert emu.world.speeds == (0, 0)


def test_a_device_prober_checks_for_none(tmp_path: Path) -> None:
    controller = tmp_path / "prober.py"
    controller.write_text(
        "from controller import Robot\n"
        "robot = Robot()\n"
        "names = ('gps', 'compass', 'ps0', 'camera')\n"
        "found = [n for n in names if robot.getDevice(n) is not None]\n"
        "print('found', ','.join(found))\n"
    )
    with Emulator("webots", seed=2) as emu:
        result = subprocess.run(
            [*ego_command(), "run", "--port", emu.path, str(controller)],
            capture_output=True,
            text=True,
            cwd=tmp_path,
            timeout=30,
        )
    assert result.returncode == 0, result.stderr
    assert result.stdout.strip() == "found ps0,camera"
    assert 'Device "gps" was not found on robot "e-puck"' in result.stderr


RED_BOX_WORLD = """
[robot]
x_m = -0.2
y_m = -0.1
heading_deg = 0

[[box]]
x_m = 0.3
y_m = 0.2
size_m = 0.08
rgb = [210, 20, 20]
"""


def test_a_colour_follower_at_52x39_drives_up_to_the_red_box(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Started with the box out of view (31 degrees left of its heading, the camera sees
    24 either side), it turns to find it and stops in front of it, facing it."""
    world_file = tmp_path / "red.toml"
    world_file.write_text(RED_BOX_WORLD)
    robots: list[Any] = []
    options = runtime.RunOptions(
        port="sim", world=str(world_file), seed=3, duration_s=20.0, on_robot=[robots.append]
    )
    run_controller(CONTROLLERS / "colour_follower.py", options)
    out = capsys.readouterr().out.split()
    assert out[:3] == ["camera", "52", "39"]  # Webots' e-puck camera, unasked
    assert out[-1] == "arrived"
    world = world_of(robots[0])
    pose, box = world.snapshot(), world.blocks[0]
    bearing = math.atan2(box.y_m - pose.y_m, box.x_m - pose.x_m)
    assert abs(math.remainder(bearing - pose.theta_rad, 2 * math.pi)) < math.radians(15)
    gap = math.hypot(box.x_m - pose.x_m, box.y_m - pose.y_m) - box.half_size_m
    assert gap < 0.2, gap  # it drove up to the box: it started 0.50 m from its face
    assert world.speeds == (0, 0)
