"""ego swarm: emulated e-pucks in one world, each controller in its own process over
Zenoh on loopback: they see each other on their proximity sensors, and talk through
Webots' Emitter and Receiver with the signal strength of their distance."""

from __future__ import annotations

import json
import math
import subprocess
from pathlib import Path

from helpers import ego_command
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
    )  # fmt: skip
    assert result.returncode == 0, result.stderr
    found = [json.loads(line[len("RESULT "):]) for line in result.stdout.splitlines()
             if line.startswith("RESULT ")]  # fmt: skip
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
