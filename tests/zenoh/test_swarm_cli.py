"""ego swarm on the command line (issue 23, item 5): each robot's own sensor noise, its
lines headed by its name, the Zenoh extra named when missing, and Ctrl-C said."""

from __future__ import annotations

import signal
import subprocess
import sys
from pathlib import Path

from helpers import ego_command
from zenoh_support import free_endpoint

from ego.app.swarm import Swarm

#: Prints its name on standard output and on standard error, then steps a little.
SPEAKER = """\
import sys
from controller import Robot
robot = Robot()
robot.step(32)
print("out from", robot.getName(), flush=True)
print("err from", robot.getName(), file=sys.stderr, flush=True)
while robot.step(32) != -1:
    pass
"""


def _still_readings(swarm: Swarm, count: int = 20) -> list[list[tuple[int, int, int]]]:
    """Each robot's accelerometer, standing still: gravity and its sensor noise alone."""
    return [[world.accelerometer_raw() for _ in range(count)] for world in swarm.worlds]


def test_each_robot_of_the_default_world_has_its_own_noise() -> None:
    with Swarm(3, seed=7, endpoint=free_endpoint()) as swarm:
        first = _still_readings(swarm)
    assert first[0] != first[1] and first[1] != first[2] and first[0] != first[2]
    with Swarm(3, seed=7, endpoint=free_endpoint()) as again:
        assert _still_readings(again) == first  # the same seed, the same noise


def test_robot_seeds_never_repeat_across_seeds_and_robots() -> None:
    from ego.app.swarm import MAX_ROBOTS, robot_seed

    seeds = [robot_seed(seed, index) for seed in range(10) for index in range(MAX_ROBOTS)]
    assert len(set(seeds)) == len(seeds)
    assert robot_seed(None, 3) is None


def test_each_line_of_a_controller_is_headed_by_its_robots_name(tmp_path: Path) -> None:
    (tmp_path / "speaker.py").write_text(SPEAKER)
    done = subprocess.run(
        [*ego_command(), "swarm", "--robots", "2", "--duration", "0.5", "--zenoh-endpoint",
         free_endpoint(), "speaker.py"],
        cwd=tmp_path, capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    for name in ("epuck0", "epuck1"):
        assert f"[{name}] out from {name}" in done.stdout.splitlines(), done.stdout
        assert f"[{name}] err from {name}" in done.stderr.splitlines(), done.stderr


def test_ego_swarm_without_zenoh_names_the_extra(tmp_path: Path) -> None:
    (tmp_path / "speaker.py").write_text(SPEAKER)
    without = ("import sys; sys.modules['zenoh'] = None; "
               "from ego.app.cli import main; sys.exit(main(sys.argv[1:]))")  # fmt: skip
    done = subprocess.run(
        [sys.executable, "-c", without, "swarm", "--robots", "2", "--zenoh-endpoint",
         free_endpoint(), "speaker.py"],
        cwd=tmp_path, capture_output=True, text=True, timeout=60,
    )  # fmt: skip
    assert done.returncode == 1
    assert done.stderr.splitlines() == [
        "ego: error: ego swarm needs eclipse-zenoh: pip install 'ego[zenoh]'"
    ]


def test_ctrl_c_under_ego_swarm_says_the_robots_stopped(tmp_path: Path) -> None:
    (tmp_path / "speaker.py").write_text(SPEAKER)
    proc = subprocess.Popen(
        [*ego_command(), "swarm", "--robots", "2", "--zenoh-endpoint", free_endpoint(),
         "speaker.py"],
        cwd=tmp_path, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
    )  # fmt: skip
    try:
        assert proc.stdout is not None
        for line in proc.stdout:
            if "out from" in line:
                break
        proc.send_signal(signal.SIGINT)  # the swarm's process only: it ends the controllers
        _, stderr = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    assert proc.returncode == 130
    assert stderr.splitlines()[-1] == "ego: stopped by Ctrl-C (robots stopped)", stderr
