"""The examples of examples/ run as a user runs them, each against the emulator, and do
what their docstrings say: checked on the emulated world's ground truth, not on what
the controller prints about itself."""

from __future__ import annotations

import math
import os
import pty
import re
import select
import socket
import subprocess
import sys
import time
from collections.abc import Iterator
from itertools import pairwise
from pathlib import Path
from typing import Any

import pytest
from helpers import assert_stopped, ego_command, wait_until

from ego.app.runner import run_controller
from ego.faces import runtime
from firmware_sim import Emulator, World
from firmware_sim.floor import LineTrack
from tests.helpers import world_of

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def ego_run(port: str, example: str, *options: str, cwd: Path) -> subprocess.Popen[str]:
    """``ego run --port PORT [options] examples/EXAMPLE``, started."""
    return subprocess.Popen(
        [*ego_command(), "run", "--port", port, *options, str(EXAMPLES / example)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        cwd=cwd,
    )


def watch(proc: subprocess.Popen[str], world: World) -> Iterator[Any]:
    """The robot's true pose every 50 ms while ``proc`` runs."""
    while proc.poll() is None:
        yield world.snapshot()
        time.sleep(0.05)  # a pace: the watch's 50 ms samples, not a wait for anything


def test_every_example_is_listed_in_the_examples_readme() -> None:
    listed = (EXAMPLES / "README.md").read_text(encoding="utf-8")
    for example in sorted(EXAMPLES.glob("*.py")):
        assert f"`{example.name}`" in listed, example.name


def test_obstacle_avoidance_never_touches_a_wall_in_the_maze(tmp_path: Path) -> None:
    with Emulator("webots", seed=2, world="maze") as emu:
        proc = ego_run(emu.path, "obstacle_avoidance.py", "--duration", "10", cwd=tmp_path)
        touched = any(emu.world.touching() for _ in watch(proc, emu.world))
        _, err = proc.communicate(timeout=30)
        assert proc.returncode == 0, err
        assert not touched
        assert emu.world.closest_approach_m > 0.002, emu.world.closest_approach_m
        assert emu.world.distance_travelled_m > 0.3  # it went somewhere
        assert_stopped(emu.world)


def test_line_following_stays_on_the_line_track(tmp_path: Path) -> None:
    with Emulator("webots", seed=1, world="line-track") as emu:
        track = emu.world.floor_pattern
        assert isinstance(track, LineTrack)
        proc = ego_run(emu.path, "line_following.py", "--duration", "8", cwd=tmp_path)
        poses = list(watch(proc, emu.world))
        _, err = proc.communicate(timeout=30)
        assert proc.returncode == 0, err
    worst = max(float(track.distance(p.x_m, p.y_m)) for p in poses)
    assert worst < 0.025, worst  # the robot's centre never left the line's neighbourhood
    travelled = sum(math.dist((a.x_m, a.y_m), (b.x_m, b.y_m)) for a, b in pairwise(poses))
    assert travelled > 0.3  # round the first corner (0.35 m ahead of the start)


def test_colour_following_ends_facing_the_red_box(capsys: pytest.CaptureFixture[str]) -> None:
    robots: list[Any] = []
    options = runtime.RunOptions(
        port="sim",
        world=str(EXAMPLES / "red_box.toml"),
        seed=3,
        duration_s=20.0,
        on_robot=[robots.append],
    )
    run_controller(EXAMPLES / "colour_following.py", options)
    out = capsys.readouterr().out.split()
    assert out[:2] == ["camera", "52x39"]
    assert out[-1] == "arrived"
    world = world_of(robots[0])
    pose, box = world.snapshot(), world.blocks[0]
    bearing = math.atan2(box.y_m - pose.y_m, box.x_m - pose.x_m)
    assert abs(math.remainder(bearing - pose.theta_rad, 2 * math.pi)) < math.radians(15)
    gap = math.hypot(box.x_m - pose.x_m, box.y_m - pose.y_m) - box.half_size_m
    assert gap < 0.2, gap  # it started 0.50 m from the box's face, facing away from it
    assert world.speeds == (0, 0)


@pytest.mark.parametrize(
    ("firmware", "expected"),
    [
        ("gctronic", ["firmware: gctronic (stock GCtronic asercom, selector 10)", "selector: 10"]),
        ("webots", ["firmware: webots (Webots e-puck firmware 1.5.x, Bluetooth)",
                    "selector: not reported"]),
    ],
)  # fmt: skip
def test_which_firmware_names_the_firmware_that_answers(
    firmware: str, expected: list[str], tmp_path: Path
) -> None:
    with Emulator(firmware, seed=1) as emu:
        done = subprocess.run(
            [sys.executable, str(EXAMPLES / "which_firmware.py"), emu.path],
            capture_output=True, text=True, timeout=60, cwd=tmp_path,
        )  # fmt: skip
        assert done.returncode == 0, done.stderr
        lines = done.stdout.splitlines()
        for line in expected:
            assert line in lines, done.stdout
        served = next(line for line in lines if line.startswith("serves:"))
        assert "proximity sensors" in served and "light sensors" in served
        if firmware == "webots":
            assert "battery" not in served  # Webots' firmware has no battery command
        assert emu.world.distance_travelled_m == 0  # it moved nothing


def _line(proc: subprocess.Popen[str]) -> str:
    assert proc.stdout is not None
    ready, _, _ = select.select([proc.stdout], [], [], 20.0)
    return proc.stdout.readline().strip() if ready else ""


def test_keyboard_teleop_drives_from_the_keys_typed_in_its_terminal(tmp_path: Path) -> None:
    with Emulator("webots", seed=1) as emu:
        master, slave = pty.openpty()
        proc = subprocess.Popen(
            [*ego_command(), "run", "--port", emu.path, str(EXAMPLES / "keyboard_teleop.py")],
            stdin=slave, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=tmp_path,
        )  # fmt: skip
        os.close(slave)
        try:
            assert _line(proc) == "arrows drive, space stops, Q quits"
            start = emu.world.snapshot()
            os.write(master, b"\x1b[A")  # up
            assert _line(proc) == "wheels +3.0 +3.0 rad/s"
            assert wait_until(lambda: emu.world.speeds == (477, 477))
            assert wait_until(lambda: emu.world.snapshot().x_m > start.x_m + 0.01)
            os.write(master, b"\x1b[C")  # right: turn clockwise on the spot
            assert _line(proc) == "wheels +1.5 -1.5 rad/s"
            assert wait_until(lambda: emu.world.snapshot().theta_rad < start.theta_rad - 0.1)
            os.write(master, b" ")
            assert _line(proc) == "wheels +0.0 +0.0 rad/s"
            assert wait_until(lambda: emu.world.speeds == (0, 0))
            os.write(master, b"q")
            assert proc.wait(timeout=20) == 0
        finally:
            if proc.poll() is None:
                proc.kill()
            proc.communicate(timeout=10)
            os.close(master)
        assert_stopped(emu.world)


def _free_zenoh_endpoint() -> str:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return f"tcp/127.0.0.1:{probe.getsockname()[1]}"


def test_a_swarm_of_three_hear_each_other_through_emitter_and_receiver(tmp_path: Path) -> None:
    pytest.importorskip("zenoh", reason="ego swarm needs eclipse-zenoh (the zenoh extra)")
    done = subprocess.run(
        [*ego_command(), "swarm", "--robots", "3", "--duration", "2",
         "--zenoh-endpoint", _free_zenoh_endpoint(), str(EXAMPLES / "swarm.py")],
        capture_output=True, text=True, timeout=120, cwd=tmp_path,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    heard: dict[str, dict[str, int]] = {}
    # Each line comes headed by the robot that printed it: "[epuck1] epuck1 heard ...".
    pattern = r"^\[(\w+)\] (\w+) heard (\w+) (\d+) times"
    for head, me, sender, count in re.findall(pattern, done.stdout, re.M):
        assert head == me  # the heading is the robot's own name
        heard.setdefault(me, {})[sender] = int(count)
    robots = {"epuck0", "epuck1", "epuck2"}
    assert set(heard) == robots, done.stdout
    for me, senders in heard.items():
        assert set(senders) == robots - {me}, (me, senders)  # every other, never itself
        assert all(count >= 10 for count in senders.values()), senders  # 2 s of 32 ms steps


def _served_url(server: subprocess.Popen[str]) -> str:
    assert server.stderr is not None
    for line in server.stderr:
        match = re.search(r"ego serve: .* on (tcp://\S+)", line)
        if match:
            return match.group(1)
    raise AssertionError(f"ego serve exited with {server.wait()} before serving")


def test_remote_control_drives_a_square_through_ego_serve_with_a_secret(tmp_path: Path) -> None:
    secret = tmp_path / "secret"
    assert subprocess.run([*ego_command(), "secret", "--out", str(secret)]).returncode == 0
    with Emulator("webots", seed=1) as emu:
        server = subprocess.Popen(
            [*ego_command(), "serve", "--port", emu.path, "--listen", "tcp://127.0.0.1:0",
             "--secret-file", str(secret)],
            stderr=subprocess.PIPE, text=True, cwd=tmp_path,
        )  # fmt: skip
        try:
            url = _served_url(server)
            without = subprocess.run(
                [sys.executable, str(EXAMPLES / "remote_control.py"), url],
                capture_output=True, text=True, timeout=60, cwd=tmp_path,
                env={k: v for k, v in os.environ.items() if not k.startswith("EGO_SECRET")},
            )  # fmt: skip
            assert without.returncode != 0
            assert "requires a shared secret" in without.stderr
            done = subprocess.run(
                [sys.executable, str(EXAMPLES / "remote_control.py"), url],
                capture_output=True, text=True, timeout=120, cwd=tmp_path,
                env={**os.environ, "EGO_SECRET_FILE": str(secret)},
            )  # fmt: skip
        finally:
            server.terminate()
            server.communicate(timeout=10)
        assert done.returncode == 0, done.stderr
        assert "corner 4:" in done.stdout, done.stdout
        left, right = (int(v) for v in done.stdout.split("encoders")[1].split())
        end = emu.world.snapshot()
        # Four sides of one wheel turn (0.128 m each) and four quarter turns on the spot
        # (323 steps a wheel, each way), and what a step overshoots: more on a loaded
        # machine, whose steps come late while the wheels turn on.
        assert emu.world.distance_travelled_m > 0.45, emu.world.distance_travelled_m
        assert right - left > 0.95 * 4 * 2 * 323, (left, right)
        # The robot truly turned as far as its encoders say: the world's heading is the
        # odometry's (wheel radius 20.5 mm, axle 53 mm).
        odometry = (right - left) / 1000 * 2 * math.pi * 0.0205 / 0.053
        error = math.remainder(end.theta_rad - odometry, 2 * math.pi)
        assert abs(error) < math.radians(10), (end, odometry)
        assert_stopped(emu.world)
