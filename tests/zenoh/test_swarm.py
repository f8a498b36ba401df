"""ego swarm: emulated e-pucks in one world, each controller in its own process over
Zenoh on loopback: they see each other on their proximity sensors, and talk through
Webots' Emitter and Receiver with the signal strength of their distance."""

from __future__ import annotations

import json
import math
import os
import re
import signal
import subprocess
import threading
from pathlib import Path

import pytest
from helpers import ego_command, run_async, wait_until
from zenoh_support import free_endpoint

TALK = Path(__file__).parent / "controllers" / "swarm_talk.py"

#: Four robots 10 cm apart in a cross, facing the centre, in an empty arena.
CROSS = """
box = []
[robot]
x_m = -0.05
y_m = 0.0
heading_deg = 0
[[robots]]
x_m = 0.05
y_m = 0.0
heading_deg = 180
[[robots]]
x_m = 0.0
y_m = 0.09
heading_deg = -90
[[robots]]
x_m = 0.0
y_m = -0.09
heading_deg = 90
"""

#: Three robots on a line, far from each other and from the walls.
LINE = """
box = []
[arena]
size_m = 2.0
[robot]
x_m = -0.4
y_m = 0.0
heading_deg = 90
[[robots]]
x_m = 0.0
y_m = 0.0
heading_deg = 90
[[robots]]
x_m = 0.5
y_m = 0.0
heading_deg = 90
"""


def _swarm(tmp_path: Path, robots: int, world: str) -> dict[str, dict[str, object]]:
    path = tmp_path / "world.toml"
    path.write_text(world)
    result = subprocess.run(
        [*ego_command(), "swarm", "--robots", str(robots), "--world", str(path),
         "--zenoh-endpoint", free_endpoint(), str(TALK)],
        capture_output=True, text=True, timeout=120, cwd=tmp_path,
        env={**os.environ, "SWARM_TALK_OTHERS": str(robots - 1)},
    )  # fmt: skip
    assert result.returncode == 0, result.stderr
    # Each line is headed by its robot's name: "[epuck0] RESULT {...}".
    found = [json.loads(line.partition("RESULT ")[2]) for line in result.stdout.splitlines()
             if "] RESULT " in line]  # fmt: skip
    return {str(r["me"]): r for r in found}


def test_a_swarm_of_four_sees_each_other_on_proximity(tmp_path: Path) -> None:
    results = _swarm(tmp_path, 4, CROSS)
    assert sorted(results) == ["epuck0", "epuck1", "epuck2", "epuck3"]
    for name, result in results.items():
        # Nothing but the others within reach (the walls are 40 cm away): they show.
        assert float(result["closest"]) > 300, (name, result)  # type: ignore[arg-type]


def test_three_robots_talk_through_emitter_and_receiver_with_their_distances(
    tmp_path: Path,
) -> None:
    results = _swarm(tmp_path, 3, LINE)
    assert sorted(results) == ["epuck0", "epuck1", "epuck2"]
    positions = {"epuck0": -0.4, "epuck1": 0.0, "epuck2": 0.5}
    for name, result in results.items():
        heard = result["heard"]
        assert isinstance(heard, dict)
        others = sorted(set(positions) - {name})
        assert sorted(heard) == others, (name, heard)  # every other robot, never itself
        assert all(count >= 20 for count in heard.values()), heard
        strength = result["strength"]
        assert isinstance(strength, dict)
        for other in others:
            distance = abs(positions[other] - positions[name])
            assert math.isclose(strength[other], 1 / distance**2, rel_tol=0.05), (name, other)
    # Nobody saw anybody on proximity: 40 cm and more apart.
    assert all(float(r["closest"]) < 200 for r in results.values())  # type: ignore[arg-type]


def test_the_swarms_dashboard_shows_every_robot_and_stops_them_all(tmp_path: Path) -> None:
    import aiohttp

    from ego.app.swarm import Swarm

    drive = tmp_path / "drive.py"
    drive.write_text(
        "from controller import Robot\n"
        "robot = Robot()\n"
        "left, right = robot.getDevice('left wheel motor'), robot.getDevice('right wheel motor')\n"
        "for m in (left, right):\n"
        "    m.setPosition(float('inf')); m.setVelocity(2.0)\n"
        "while robot.step(32) != -1:\n"
        "    pass\n"
    )
    with Swarm(3, endpoint=free_endpoint()) as swarm:
        url = swarm.serve_dashboard("127.0.0.1:0")
        runner = threading.Thread(
            target=swarm.run_controllers, args=([str(drive)],), kwargs={"duration_s": 4.0}
        )
        runner.start()

        async def look_then_stop() -> tuple[dict[str, object], dict[str, object]]:
            from ego.servers.dashboard.access import socket_url

            ws_url = socket_url(url)
            async with aiohttp.ClientSession() as session, session.ws_connect(ws_url) as ws:
                hello = await ws.receive_json()
                sample: dict[str, object] = {}
                while "swarm" not in sample:
                    message = json.loads((await ws.receive()).data)
                    sample = message if message["type"] == "sample" else sample
                await ws.send_json({"type": "take"})
                await ws.send_json({"type": "stop"})
                await ws.receive()
            return hello, sample

        hello, sample = run_async(look_then_stop())
        stopped = [w.speeds for w in swarm.worlds]
        runner.join(30)
    assert hello["mode"] == "swarm" and hello["robots"] == ["epuck0", "epuck1", "epuck2"]
    swarm_poses = sample["swarm"]
    assert isinstance(swarm_poses, list) and [p[0] for p in swarm_poses] == hello["robots"]
    assert all(speeds == (0, 0) for speeds in stopped), stopped


def test_a_controllers_child_that_holds_its_output_open_is_a_thread_leak(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    # Its relay cannot end while the child lives: run_controllers says so (issue 35),
    # where it logged a warning and left Python waiting at exit without a word.
    from ego.app.swarm import Swarm
    from ego.errors import ThreadLeakError

    controller = tmp_path / "spawn.py"
    controller.write_text(
        "import subprocess, sys\n"
        "child = subprocess.Popen([sys.executable, '-c', 'import time; time.sleep(120)'])\n"
        "print('CHILD', child.pid, flush=True)\n"
    )

    def relays() -> list[threading.Thread]:
        return [t for t in threading.enumerate() if t.name == "ego-swarm-relay [epuck0]"]

    leak = r"ego-swarm-relay \[epuck0\].*own child process"
    try:
        with (
            Swarm(1, endpoint=free_endpoint()) as swarm,
            pytest.raises(ThreadLeakError, match=leak),
        ):
            swarm.run_controllers([str(controller)])
        assert relays()  # still running, still owned: nothing was dropped
    finally:
        out = capsys.readouterr().out
        for pid in re.findall(r"\[epuck0\] CHILD (\d+)", out):
            os.kill(int(pid), signal.SIGKILL)
    assert "[epuck0] CHILD" in out
    assert wait_until(lambda: not relays(), timeout_s=10)
