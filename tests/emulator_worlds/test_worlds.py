"""World files for the emulator: built-in worlds, TOML files, a line follower on the line
track, and the ground-truth devices a world may declare."""

from __future__ import annotations

import json
import math
import subprocess
from itertools import pairwise
from pathlib import Path

import pytest
from helpers import ego_command
from mcap.reader import make_reader

import ego
from firmware_sim import Emulator
from firmware_sim.floor import LineTrack
from firmware_sim.worlds import BUILT_IN, load_world
from tests.helpers import world_of

CONTROLLERS = Path(__file__).parents[1] / "faces" / "controllers"


@pytest.mark.parametrize("name", BUILT_IN)
def test_each_built_in_world_loads_and_starts_the_robot_on_a_free_spot(name: str) -> None:
    world = load_world(name, seed=1)
    pose = world.snapshot()
    assert abs(pose.x_m) < world.arena.half_size_m and abs(pose.y_m) < world.arena.half_size_m
    assert world._clearance() > 0.01  # not in a wall or a box


def test_the_line_track_starts_the_robot_on_its_line() -> None:
    world = load_world("line-track", seed=1)
    assert isinstance(world.floor_pattern, LineTrack)
    left, middle, right = world.floor()
    assert middle < 500 < min(left, right)  # black under the middle sensor only


@pytest.mark.parametrize(
    ("text", "error"),
    [
        ("[robot]\nx_m = 0\nspeed = 3\n", "unknown key 'speed' in \\[robot\\]"),
        ("colour = 'red'\n", "unknown key 'colour'"),
        ("[arena]\nsize_m = 'big'\n", "size_m = 'big' is not a number"),
        ("[arena]\nsize_m = 100\n", "size_m = 100 is not a number in 0.2..10.0"),
        ("[floor]\nkind = 'carpet'\n", "floor kind 'carpet' is not marks or track"),
        ("[floor]\nkind = 'track'\npoints = [[0, 0]]\n", "at least two points"),
        ("[[box]]\nrgb = [1, 2]\n", "three integers"),
        ("devices = ['radar']\n", "devices must be some of"),
        ("[arena\n", "not TOML"),
    ],
)
def test_a_bad_world_file_is_refused_naming_the_file_and_the_key(
    tmp_path: Path, text: str, error: str
) -> None:
    path = tmp_path / "bad.toml"
    path.write_text(text)
    with pytest.raises(ValueError, match=error) as info:
        load_world(path)
    assert str(path) in str(info.value)


def test_an_unknown_world_name_lists_the_built_in_ones() -> None:
    with pytest.raises(ValueError, match="arena, line-track, maze, light"):
        load_world("moon")


def test_a_robot_on_a_world_file(tmp_path: Path) -> None:
    path = tmp_path / "mine.toml"
    path.write_text("box = []\n[robot]\nx_m = 0.1\ny_m = 0.2\nheading_deg = 90\n")
    with ego.Robot("sim", world=str(path), seed=1) as robot:
        pose = world_of(robot).snapshot()
        assert (pose.x_m, pose.y_m) == (0.1, 0.2)
        assert pose.theta_rad == pytest.approx(math.pi / 2)
        assert world_of(robot).blocks == []


def test_a_world_is_refused_for_a_real_serial_port() -> None:
    with Emulator("webots", seed=1) as emu, pytest.raises(ValueError, match="world"):
        ego.Robot(emu.path, world="maze")


def test_a_line_follower_follows_the_line_track(tmp_path: Path) -> None:
    """Run unchanged through ego run on the line-track world; the robot stays on the line.

    In virtual time (--fast): what is tested is the controller on the world, so its steps
    are never late, however busy the machine (on the wall clock, a step 200 ms late on a
    loaded machine let it drive off the line blind). The true poses come from the run's
    recording (/ego/pose/truth)."""
    with Emulator("webots", seed=1, world="line-track") as emu:  # the track's geometry
        track = emu.world.floor_pattern
    assert isinstance(track, LineTrack)
    recording = tmp_path / "run.mcap"
    result = subprocess.run(
        [*ego_command(), "run", "--port", "sim", "--fast", "--world", "line-track",
         "--seed", "1", "--duration", "6", "--record", str(recording),
         str(CONTROLLERS / "line_follower.py")],
        capture_output=True, text=True, cwd=tmp_path, timeout=120,
    )  # fmt: skip
    assert result.returncode == 0, result.stderr
    poses = []
    with recording.open("rb") as f:
        for _, _, message in make_reader(f).iter_messages(topics=["/ego/pose/truth"]):
            position = json.loads(message.data)["pose"]["position"]
            poses.append((position["x"], position["y"]))
    assert len(poses) >= 180  # 6 s of 32 ms steps
    travelled = sum(math.hypot(bx - ax, by - ay) for (ax, ay), (bx, by) in pairwise(poses))
    worst = max(float(track.distance(x, y)) for x, y in poses)
    assert travelled > 0.15  # it moved along the track ...
    assert worst < 0.025, worst  # ... and its centre never left the line's neighbourhood


def test_declared_ground_truth_devices_read_the_world(tmp_path: Path) -> None:
    controller = tmp_path / "localise.py"
    controller.write_text(
        "from controller import Robot\n"
        "robot = Robot()\n"
        "gps = robot.getDevice('gps'); gps.enable(32)\n"
        "compass = robot.getDevice('compass'); compass.enable(32)\n"
        "robot.step(32)\n"
        "print('gps', *gps.getValues())\n"
        "print('compass', *compass.getValues())\n"
        "print('touch', robot.getDevice('touch sensor'))\n"
    )
    result = subprocess.run(
        [*ego_command(), "run", "--port", "sim", "--world", "line-track", str(controller)],
        capture_output=True, text=True, cwd=tmp_path, timeout=60,
    )  # fmt: skip
    assert result.returncode == 0, result.stderr
    lines = dict(line.split(" ", 1) for line in result.stdout.strip().splitlines())
    x, y, z = map(float, lines["gps"].split())
    assert (x, y, z) == pytest.approx((0.0, -0.35, 0.0), abs=0.005)
    north = list(map(float, lines["compass"].split()))
    assert north == pytest.approx([0.0, 1.0, 0.0], abs=0.01)  # heading east: north is left
    assert lines["touch"] == "None"  # line-track declares no touch sensor
    assert 'Device "touch sensor" was not found' in result.stderr


def test_ground_truth_devices_do_not_exist_on_a_real_robot(tmp_path: Path) -> None:
    with Emulator("webots", seed=1, world="line-track") as emu:
        controller = tmp_path / "probe.py"
        controller.write_text("from controller import Robot\nprint(Robot().getDevice('gps'))\n")
        result = subprocess.run(
            [*ego_command(), "run", "--port", emu.path, str(controller)],
            capture_output=True, text=True, cwd=tmp_path, timeout=60,
        )  # fmt: skip
    # A pty is a serial port: ego cannot see the emulator behind it, as on a real robot.
    assert result.stdout.strip() == "None"
