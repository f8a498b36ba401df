"""Published worlds as Webots writes them, run unchanged under ``ego run``: an arena off
the origin and turned, with a GPS and a Compass in the E-puck's turret slot, and an older
world declared NUE, whose Supervisor controller computes in x-z. Each answer is the one
Webots gives, in the world's own frame."""

from __future__ import annotations

import math
import subprocess
from pathlib import Path

import pytest
from helpers import ego_command
from wbt_frame_worlds import NUE_WORLD, OFF_ORIGIN


def _run(tmp_path: Path, world: str, source: str) -> dict[str, list[float]]:
    path = tmp_path / "world.wbt"
    path.write_text(world)
    controller = tmp_path / "controller_under_test.py"
    controller.write_text(source)
    result = subprocess.run(
        [*ego_command(), "run", "--port", "sim", "--fast", "--seed", "1", "--world",
         str(path), str(controller)],
        capture_output=True, text=True, cwd=tmp_path, timeout=120,
    )  # fmt: skip
    assert result.returncode == 0, result.stderr
    return {
        line.split()[0]: [float(v) for v in line.split()[1:]]
        for line in result.stdout.splitlines()
        if line.split() and line.split()[0].isidentifier()
    }


READS_THE_TURNED_ARENA = """
from controller import Supervisor

robot = Supervisor()
gps, compass = robot.getDevice("gps"), robot.getDevice("compass")
gps.enable(32)
compass.enable(32)
robot.step(32)
me, crate = robot.getSelf(), robot.getFromDef("CRATE")
print("me", *me.getPosition(), *me.getField("rotation").getSFRotation())
print("crate", *crate.getPosition())
print("gps", *gps.getValues())
print("compass", *compass.getValues())
crate.getField("translation").setSFVec3f([1.8, 1.2, 0.05])
robot.step(32)
print("moved", *crate.getPosition())
"""


def test_a_turned_arena_off_the_origin_and_a_turret_gps_answer_in_the_world_frame(
    tmp_path: Path,
) -> None:
    said = _run(tmp_path, OFF_ORIGIN, READS_THE_TURNED_ARENA)
    assert said["me"] == pytest.approx([1.9, 0.9, 0.0, 0.0, 0.0, 1.0, math.pi], abs=1e-5)
    assert said["crate"] == pytest.approx([2.1, 1.3, 0.05], abs=1e-6)
    # Webots' GPS reads where the device is: the turret slot, 9.5 mm behind the centre
    # and 48.6 mm up, the robot facing world -x.
    assert said["gps"] == pytest.approx([1.9095, 0.9, 0.0486], abs=1e-5)
    assert said["compass"] == pytest.approx([0.0, -1.0, 0.0], abs=1e-5)
    assert said["moved"] == pytest.approx([1.8, 1.2, 0.05], abs=1e-6)


#: A controller of the NUE days: the robot's forward is its -z, the floor is x-z.
COMPUTES_IN_X_Z = """
import math
from controller import Supervisor

robot = Supervisor()
me, box = robot.getSelf(), robot.getFromDef("BOX")
gps = robot.getDevice("gps")
gps.enable(32)
m = me.getOrientation()
print("start", *me.getPosition(), *me.getField("rotation").getSFRotation())
print("forward", -m[2], -m[5], -m[8])
print("box", *box.getPosition(), box.getField("rotation").getSFRotation()[3])
box.getField("translation").setSFVec3f([0.3, 0.025, 0.1])
box.getField("rotation").setSFRotation([0, 1, 0, -0.25])
left, right = robot.getDevice("left wheel motor"), robot.getDevice("right wheel motor")
for motor in (left, right):
    motor.setPosition(float("inf"))
    motor.setVelocity(3.0)
for _ in range(30):
    robot.step(32)
print("end", *me.getPosition())
print("gps", *gps.getValues())
print("moved", *box.getPosition(), box.getField("rotation").getSFRotation()[3])
"""


def test_an_nue_world_answers_in_its_own_numbers_so_x_z_controllers_work(
    tmp_path: Path,
) -> None:
    said = _run(tmp_path, NUE_WORLD, COMPUTES_IN_X_Z)
    assert said["start"] == pytest.approx([-0.1, 0.0, 0.2, 0.0, 1.0, 0.0, 1.0], abs=1e-6)
    assert said["forward"] == pytest.approx([-math.sin(1.0), 0.0, -math.cos(1.0)], abs=1e-6)
    assert said["box"] == pytest.approx([0.2, 0.025, -0.1, 0.5], abs=1e-6)
    assert said["moved"] == pytest.approx([0.3, 0.025, 0.1, -0.25], abs=1e-6)
    # Driven straight ahead, the robot went along the forward it read, on the x-z floor.
    start, end = said["start"], said["end"]
    dx, dy, dz = (end[i] - start[i] for i in range(3))
    travelled = math.hypot(dx, dz)
    assert travelled > 0.04 and dy == pytest.approx(0.0, abs=1e-9)
    assert (dx / travelled, dz / travelled) == pytest.approx(
        (-math.sin(1.0), -math.cos(1.0)), abs=0.02
    )
    # The GPS in the ground slot, 3 cm ahead of the centre, reads in the same numbers.
    gx, gy, gz = said["gps"]
    assert gy == pytest.approx(0.0003, abs=1e-6)
    assert (gx - end[0], gz - end[2]) == pytest.approx(
        (-0.03 * math.sin(1.0), -0.03 * math.cos(1.0)), abs=2e-3
    )
