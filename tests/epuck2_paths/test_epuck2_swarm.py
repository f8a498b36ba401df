"""``ego swarm --robot epuck2``: emulated e-puck2s in one world as Zenoh nodes, each
controller in its own process reaching its robot's e-puck2 devices (issue 25, item 5)."""

from __future__ import annotations

import socket
import subprocess
from pathlib import Path

from helpers import ego_command

#: Reads its tof and gyro while it turns on the spot; prints what it saw.
TURNER = """\
from controller import Robot
robot = Robot()
tof, gyro = robot.getDevice("tof"), robot.getDevice("gyro")
tof.enable(32)
gyro.enable(32)
left, right = robot.getDevice("left wheel motor"), robot.getDevice("right wheel motor")
for motor in (left, right):
    motor.setPosition(float("inf"))
left.setVelocity(-3.0)
right.setVelocity(3.0)
turn = []
while robot.step(32) != -1:
    turn.append(gyro.getValues()[2])
print(robot.getName(), "tof", round(tof.getValue()), "turning", max(turn) > 0, flush=True)
"""


def _free_endpoint() -> str:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return f"tcp/127.0.0.1:{probe.getsockname()[1]}"


def test_a_swarm_of_e_puck2s_reads_their_tof_and_gyro(tmp_path: Path) -> None:
    (tmp_path / "turner.py").write_text(TURNER)
    done = subprocess.run(
        [*ego_command(), "swarm", "--robot", "epuck2", "--robots", "2", "--duration", "1",
         "--zenoh-endpoint", _free_endpoint(), "turner.py"],
        cwd=tmp_path, capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    for name in ("epuck0", "epuck1"):
        line = next(x for x in done.stdout.splitlines() if x.startswith(f"[{name}] {name} tof"))
        tof = int(line.split()[3])
        assert 0 <= tof <= 8191, line  # the robot's millimetres, unchanged (issue 32)
        assert line.endswith("turning True"), line  # counter-clockwise: the gyro's z > 0
