"""Supervisors in a swarm (issue 36, item 4): a deepbots-shaped emitter/receiver pair
under ``ego swarm`` on a .wbt world. A bodiless ``Robot { supervisor TRUE }`` node's
controller sends actions over its Emitter, the two e-pucks answer observations over
theirs, and each episode is reset through the Supervisor; the robots' own controllers
are Supervisors too, finding each other by DEF name."""

from __future__ import annotations

import json
import math
import subprocess
from pathlib import Path

from helpers import ego_command
from zenoh_support import free_endpoint

PROJECT = Path(__file__).parent / "supervised"
WORLD = PROJECT / "worlds" / "arena.wbt"
ROBOT = PROJECT / "controllers" / "csv_robot" / "csv_robot.py"


def test_a_bodiless_supervisor_trains_two_robots_over_the_radio(tmp_path: Path) -> None:
    result = subprocess.run(
        [*ego_command(), "swarm", "--robots", "2", "--world", str(WORLD),
         "--zenoh-endpoint", free_endpoint(), str(ROBOT)],
        capture_output=True, text=True, timeout=240, cwd=tmp_path,
    )  # fmt: skip
    assert result.returncode == 0, result.stderr[-3000:]
    found = {line.partition("] ")[0].lstrip("["): json.loads(line.partition("RESULT ")[2])
             for line in result.stdout.splitlines() if "] RESULT " in line}  # fmt: skip
    assert sorted(found) == ["epuck0", "epuck1", "trainer"], result.stdout[-3000:]
    trainer = found["trainer"]
    assert trainer["me"] == "trainer" and trainer["self"] == "Robot"
    assert trainer["names"] == ["EPUCK_A", "EPUCK_B"]
    assert len(trainer["episodes"]) == 3
    for episode in trainer["episodes"]:
        for robot in ("EPUCK_A", "EPUCK_B"):
            # Observations came back over the radio during the episode, and the actions
            # drove the robot (the supervisor steps until they have moved 2 cm: a robot
            # the actions never reach hangs the run into the timeout).
            assert episode["heard"].get(robot, 0) >= 1, episode
            assert episode["moved"][robot] > 0.02, episode
            # simulationReset put it back at its start, as getFromDef reads it.
            assert episode["back"][robot] < 0.001, episode
    assert trainer["box"] == [0.1, 0.35, 0.025]  # setSFVec3f moved it; z on the floor
    a, b = found["epuck0"], found["epuck1"]
    assert (a["me"], b["me"]) == ("EPUCK_A", "EPUCK_B")
    assert math.isclose(a["other_x"], 0.2) and math.isclose(b["other_x"], -0.2)
    assert a["kind"] == b["kind"] == "E-puck"
    assert a["actions"] > 0 and b["actions"] > 0


def test_a_supervisor_whose_controller_is_missing_is_refused_in_one_line(
    tmp_path: Path,
) -> None:
    (tmp_path / "worlds").mkdir()
    world = tmp_path / "worlds" / "w.wbt"
    world.write_text(WORLD.read_text().replace('controller "trainer"', 'controller "absent"'))
    result = subprocess.run(
        [*ego_command(), "swarm", "--robots", "2", "--world", str(world),
         "--zenoh-endpoint", free_endpoint(), str(ROBOT)],
        capture_output=True, text=True, timeout=120, cwd=tmp_path,
    )  # fmt: skip
    assert result.returncode != 0
    last = result.stderr.strip().splitlines()[-1]
    assert "the supervisor's controller 'absent' is not at" in last, result.stderr
    assert "controllers/absent/absent.py" in last and "Traceback" not in result.stderr
