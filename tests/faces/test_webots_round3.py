"""Webots patterns published controllers use, round 3: every device class subclassed and
made by name, a reset that puts the motors back as Webots' does, and a controller that
ignores -1 ended as Webots ends it. Each runs unchanged under ``ego run``."""

from __future__ import annotations

import math
import re
import subprocess
import sys
import threading
from pathlib import Path
from typing import Any

import pytest
from helpers import ego_command

CONTROLLERS = Path(__file__).parent / "controllers"

#: Every class ``getDevice`` can return on the emulator, with a device of it and a call
#: that reads it: the e-puck2's devices (it has the gyro), the ground-truth devices the
#: world below declares, and Zenoh's radio.
EVERY_DEVICE = {
    "DistanceSensor": ("ps0", "getValue()"),
    "LightSensor": ("ls0", "getValue()"),
    "LED": ("led0", "get()"),
    "Motor": ("left wheel motor", "getMaxVelocity()"),
    "PositionSensor": ("left wheel sensor", "getValue()"),
    "Accelerometer": ("accelerometer", "getValues()[2]"),
    "Camera": ("camera", "getWidth()"),
    "Gyro": ("gyro", "getSamplingPeriod()"),
    "Speaker": ("speaker", "isSpeaking()"),
    "Emitter": ("emitter", "getChannel()"),
    "Receiver": ("receiver", "getQueueLength()"),
    "GPS": ("gps", "getValues()[0]"),
    "Compass": ("compass", "getValues()[1]"),
    "TouchSensor": ("touch sensor", "getValue()"),
}

GROUND_TRUTH_WORLD = """
devices = ["gps", "compass", "touch sensor"]

[arena]
size_m = 1.0

[robot]
x_m = 0.1
y_m = -0.2
heading_deg = 90
"""

#: A course's style: the subclass's own ``__init__`` takes no name and passes it up.
_SUBCLASSED = """
class Own{cls}({cls}):
    def __init__(self):
        super().__init__({name!r})
        self.mine = "{cls}"
"""


def _run(tmp_path: Path, source: str, *args: str) -> subprocess.CompletedProcess[str]:
    controller = tmp_path / "controller_under_test.py"
    controller.write_text(source)
    return subprocess.run(
        [*ego_command(), "run", "--port", "sim", "--fast", *args, str(controller)],
        capture_output=True, text=True, cwd=tmp_path, timeout=120,
    )  # fmt: skip


def _subclassing_controller(classes: list[str]) -> str:
    lines = [f"from controller import Robot, {', '.join(classes)}", "robot = Robot()"]
    for cls in classes:
        lines.append(_SUBCLASSED.format(cls=cls, name=EVERY_DEVICE[cls][0]))
    for cls in classes:
        name = EVERY_DEVICE[cls][0]
        lines += [
            f"own, plain = Own{cls}(), {cls}({name!r})",
            "for d in (own, plain):",
            "    getattr(d, 'enable', lambda p: None)(32)",
        ]
    lines.append("robot.step(32)")
    for cls in classes:
        name, call = EVERY_DEVICE[cls]
        lines += [
            f"own, plain, served = Own{cls}(), {cls}({name!r}), robot.getDevice({name!r})",
            f"assert type(served).__name__ == {cls!r}, type(served)",
            f"print({cls!r}, type(own).__name__, own.mine, own.getName(),"
            f" own.{call} == served.{call}, plain.{call} == served.{call})",
        ]
    return "\n".join(lines) + "\n"


def test_every_device_class_can_be_subclassed_and_made_by_name(tmp_path: Path) -> None:
    world = tmp_path / "truth.toml"
    world.write_text(GROUND_TRUTH_WORLD)
    # The emulated e-puck2 has the gyro and the speaker (no camera); the e-puck the others.
    runs = {
        "epuck": [c for c in EVERY_DEVICE if c not in ("Gyro", "Speaker")],
        "epuck2": ["Gyro", "Speaker", "LED"],
    }
    said: dict[str, list[str]] = {}
    for robot, classes in runs.items():
        result = _run(tmp_path, _subclassing_controller(classes), "--robot", robot,
                      "--world", str(world))  # fmt: skip
        assert result.returncode == 0, result.stderr
        said |= {line.split()[0]: line.split()[1:] for line in result.stdout.splitlines()}
    assert sorted(said) == sorted(EVERY_DEVICE)
    for cls, (name, _) in EVERY_DEVICE.items():
        assert said[cls] == [f"Own{cls}", cls, *name.split(), "True", "True"], cls


EPISODES_WORLD = """
[arena]
size_m = 1.0

[robot]
x_m = -0.2
y_m = 0.1
heading_deg = 30
"""


def test_a_deepbots_environment_starts_every_episode_where_the_world_began(
    tmp_path: Path,
) -> None:
    # deepbots' reset() steps once after simulationReset: the motors must hold, as
    # Webots' WbMotor::reset leaves them, not replay the last action (4 mm, 0.08 rad off).
    world = tmp_path / "episodes.toml"
    world.write_text(EPISODES_WORLD)
    result = subprocess.run(
        [*ego_command(), "run", "--port", "sim", "--fast", "--world", str(world), "--seed", "5",
         str(CONTROLLERS / "deepbots_episodes.py")],
        capture_output=True, text=True, cwd=tmp_path, timeout=120,
    )  # fmt: skip
    assert result.returncode == 0, result.stderr
    starts = [line.split()[2:] for line in result.stdout.splitlines() if line.startswith("episode")]
    moved = [float(line.split()[2]) for line in result.stdout.splitlines()
             if line.startswith("moved")]  # fmt: skip
    assert len(starts) == 5 and len(moved) == 5
    for x, y, yaw in ([float(v) for v in start] for start in starts):
        assert math.hypot(x + 0.2, y - 0.1) < 0.001
        assert abs(yaw - math.radians(30)) < 0.01
    assert min(moved) > 0.05  # every episode drove off its start
    # The wheels as Webots' reset leaves them: held at 0 rad, velocity back at its maximum.
    motors = [line.split()[2:] for line in result.stdout.splitlines() if line.startswith("motor")]
    assert motors == [["0.0", "True", "0.0"]] * 5


#: A published Q-learning loop's shape: the episode loop never looks at step()'s -1.
#: It notes when -1 first came, and (in ``finally``, which Webots' kill would skip, only
#: to measure) how long after it the controller was ended, on the clock ego uses.
IGNORES_MINUS_ONE = """
import time
from controller import Robot

robot = Robot()
left = robot.getDevice("left wheel motor")
left.setPosition(float("inf"))
left.setVelocity(3.0)
first, episodes = None, 0
try:
    while True:
        episodes += 1
        for _ in range(10):
            if robot.step(32) == -1 and first is None:
                first = time.monotonic()
                print("minus one", flush=True)
finally:
    print("ended after", time.monotonic() - first, "episodes", episodes, flush=True)
"""


def _ended_as_webots_ends_it(result: subprocess.CompletedProcess[str]) -> float:
    """The controller's grace, checked: one line, the documented status."""
    from ego.faces.termination import GRACE_S, TERMINATED_STATUS

    assert result.returncode == TERMINATED_STATUS, result.stderr
    lines = result.stdout.splitlines()
    assert lines[0] == "minus one"
    ended = lines[-1].split()
    elapsed = float(ended[2])
    # Ended at its first step() after the grace: never before it; after it, within the
    # margin docs/webots-compat.md allows a busy machine (one second more).
    assert GRACE_S <= elapsed < GRACE_S + 1.0
    said = [line for line in result.stderr.splitlines() if line.startswith("ego: ")]
    assert len(said) == 1, result.stderr
    line = re.fullmatch(
        r"ego: the controller was ended (\d+\.\d) s after step\(\) returned -1 \(the run's "
        r"--duration of 0\.5 s was up\), as Webots ends a controller that goes on",
        said[0],
    )
    assert line is not None, said
    # Said when ended, before the controller's finally measured (rounded to 0.1 s).
    assert GRACE_S <= float(line[1]) <= elapsed + 0.05
    assert "Traceback" not in result.stderr
    return elapsed


def test_a_controller_that_ignores_minus_one_is_ended_on_the_emulator(tmp_path: Path) -> None:
    result = _run(tmp_path, IGNORES_MINUS_ONE, "--duration", "0.5")
    _ended_as_webots_ends_it(result)


def test_a_controller_that_ignores_minus_one_is_ended_on_a_serial_robot(
    tmp_path: Path,
) -> None:
    from helpers import assert_stopped

    from firmware_sim import Emulator

    controller = tmp_path / "ignores.py"
    controller.write_text(IGNORES_MINUS_ONE)
    with Emulator("webots", seed=3) as emu:  # behind a pty: to ego, a real serial robot
        result = subprocess.run(
            [*ego_command(), "run", "--port", emu.path, "--duration", "0.5", str(controller)],
            capture_output=True, text=True, cwd=tmp_path, timeout=120,
        )  # fmt: skip
        _ended_as_webots_ends_it(result)
        assert_stopped(emu.world)  # stopped at the first -1, before the grace


def test_step_begin_returns_while_the_step_runs_and_step_end_collects_it(
    webots_robot: Any, emulator: Any, caplog: Any
) -> None:
    # The step's own work (a core step listener) waits for the controller to have worked
    # after stepBegin: if stepBegin ran the whole step itself, the controller could never
    # work during it, and the step would give up waiting.
    worked = threading.Event()
    seen_work: list[bool] = []
    webots_robot.core.add_step_listener(lambda core: seen_work.append(worked.wait(10.0)))
    ps0 = webots_robot.getDevice("ps0")
    left = webots_robot.getDevice("left wheel motor")
    ps0.enable(32)
    left.setPosition(float("inf"))
    answered = len(emulator.history)
    interval = sys.getswitchinterval()
    for step in range(3):
        worked.clear()
        assert webots_robot.stepBegin(32) == 0
        left.setVelocity(2.0 + step)  # the controller's work, during the step
        worked.set()
        assert webots_robot.stepEnd() == 0
    assert seen_work == [True, True, True]
    assert sys.getswitchinterval() == interval  # the interpreter's own, given back
    # A speed set while its batch was in flight is not taken for a misread reply.
    assert not [r for r in caplog.records if "implausible" in r.getMessage()]
    assert len(emulator.history) >= answered + 3  # each step's batch went to the robot
    assert ps0.getValue() == ps0.getValue() and ps0.getValue() > 0  # a value, not NaN
    assert webots_robot.stepEnd() == 0  # none begun: nothing to wait for
    # The last speed set during a step goes with the next batch.
    assert webots_robot.step(32) == 0
    assert emulator.world.speeds[0] == round(4.0 / 0.00628)


#: A navigation lab as Webots writes it: a goal drawn as a flat Plane and a start mark
#: as a thin Cylinder, Solids with DEF names and no box, beside a box and the e-puck.
MARKED_WORLD = """#VRML_SIM R2023b utf8
EXTERNPROTO "https://raw.githubusercontent.com/cyberbotics/webots/R2023b/projects/objects/floors/protos/RectangleArena.proto"
WorldInfo { basicTimeStep 32 }
RectangleArena { floorSize 1 1 }
DEF GOAL Solid {
  translation 0.3 0.25 0.001
  rotation 0 0 1 0.5
  children [
    Shape {
      appearance PBRAppearance { baseColor 0 1 0 }
      geometry Plane { size 0.1 0.1 }
    }
  ]
  name "goal"
}
DEF START_MARK Solid {
  translation -0.2 -0.1 0.0005
  children [ Shape { geometry Cylinder { height 0.001 radius 0.03 } } ]
  name "start mark"
}
DEF BOX Solid {
  translation 0 0.3 0.025
  children [ Shape { geometry Box { size 0.05 0.05 0.05 } } ]
  boundingObject Box { size 0.05 0.05 0.05 }
}
DEF ME E-puck { translation -0.2 -0.1 0 controller "supervised" supervisor TRUE }
"""

SEEKS_THE_GOAL = """
from controller import Supervisor

robot = Supervisor()
goal, mark = robot.getFromDef("GOAL"), robot.getFromDef("START_MARK")
print("goal", goal.getTypeName(), *goal.getPosition(), goal.getField("rotation").getSFRotation()[3])
print("mark", mark.getTypeName(), *mark.getPosition())
goal.getField("translation").setSFVec3f([-0.3, 0.1, 0.001])
robot.step(32)
print("moved", *goal.getPosition())
robot.simulationReset()
robot.step(32)
print("reset", *goal.getPosition())
"""


def test_get_from_def_finds_a_named_solid_of_any_shape(tmp_path: Path) -> None:
    world = tmp_path / "marked.wbt"
    world.write_text(MARKED_WORLD)
    result = _run(tmp_path, SEEKS_THE_GOAL, "--world", str(world))
    assert result.returncode == 0, result.stderr
    said = {line.split()[0]: line.split()[1:] for line in result.stdout.splitlines()}
    assert said["goal"][0] == "Solid" and said["mark"][0] == "Solid"
    assert [float(v) for v in said["goal"][1:]] == pytest.approx([0.3, 0.25, 0.001, 0.5])
    assert [float(v) for v in said["mark"][1:]] == pytest.approx([-0.2, -0.1, 0.0005])
    assert [float(v) for v in said["moved"]] == pytest.approx([-0.3, 0.1, 0.001])
    assert [float(v) for v in said["reset"]] == pytest.approx([0.3, 0.25, 0.001])
