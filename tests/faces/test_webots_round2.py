"""Webots patterns published controllers use, round 2: subclassed devices and robots,
Webots' per-class submodules, the attributes Webots leaves plain, deprecated getters of
absent devices, and a step loop that overruns. Each runs unchanged under ``ego run``."""

from __future__ import annotations

import inspect
import math
import subprocess
from pathlib import Path

import pytest
from helpers import ego_command

import ego.controller as face
from ego.core.overrun_report import OverrunReport
from firmware_sim import Emulator

CONTROLLERS = Path(__file__).parent / "controllers"

#: Webots' Python controller module, one submodule per class
#: (cyberbotics/webots lib/controller/python/controller/*.py), and the names each holds.
WEBOTS_SUBMODULES = {
    "accelerometer": ["Accelerometer"], "altimeter": ["Altimeter"], "ansi_codes": ["AnsiCodes"],
    "brake": ["Brake"], "camera": ["Camera", "CameraRecognitionObject"],
    "compass": ["Compass"], "connector": ["Connector"], "device": ["Device"],
    "display": ["Display"], "distance_sensor": ["DistanceSensor"], "emitter": ["Emitter"],
    "field": ["Field"], "gps": ["GPS"], "gyro": ["Gyro"], "inertial_unit": ["InertialUnit"],
    "joystick": ["Joystick"], "keyboard": ["Keyboard"], "led": ["LED"], "lidar": ["Lidar"],
    "lidar_point": ["LidarPoint"], "light_sensor": ["LightSensor"], "motion": ["Motion"],
    "motor": ["Motor"], "mouse": ["Mouse"], "node": ["Node"], "pen": ["Pen"],
    "position_sensor": ["PositionSensor"], "radar": ["Radar"], "radar_target": ["RadarTarget"],
    "range_finder": ["RangeFinder"], "receiver": ["Receiver"], "robot": ["Robot"],
    "sensor": ["Sensor"], "skin": ["Skin"], "speaker": ["Speaker"],
    "supervisor": ["Supervisor"], "touch_sensor": ["TouchSensor"],
    "vacuum_gripper": ["VacuumGripper"],
}  # fmt: skip

_DEVICE = {"name": False, "model": False, "node_type": False}
_SENSOR = {**_DEVICE, "sampling_period": True}
#: The properties of Webots' classes (read-only False, settable True), as its sources
#: declare them, for the properties ego serves. Anything else is a plain attribute a
#: controller may set.
WEBOTS_PROPERTIES: dict[type, dict[str, bool]] = {
    face.Device: _DEVICE,
    face.Sensor: _SENSOR,
    face.DistanceSensor: {**_SENSOR, **dict.fromkeys(
        ("aperture", "lookup_table", "max_value", "min_value", "type", "value"), False)},
    face.LightSensor: {**_SENSOR, "lookup_table": False, "value": False},
    face.Accelerometer: {**_SENSOR, "lookup_table": False, "value": False},
    face.PositionSensor: {**_SENSOR, **dict.fromkeys(("brake", "motor", "type", "value"), False)},
    face.Motor: {**_DEVICE, **dict.fromkeys(
        ("brake", "position_sensor", "max_position", "min_position", "max_velocity", "type"),
        False), "target_position": True, "target_velocity": True, "target_acceleration": True},
    face.LED: {**_DEVICE, "value": True},
    face.Camera: {**_SENSOR, **dict.fromkeys(
        ("image", "focal_length", "max_focal_distance", "min_focal_distance", "height", "width",
         "min_fov", "max_fov", "near"), False),
        "exposure": True, "focal_distance": True, "fov": True},
    face.Robot: {**dict.fromkeys(
        ("basic_time_step", "name", "model", "project_path", "world_path", "supervisor",
         "synchronization", "time", "number_of_devices", "mode"), False),
        "custom_data": True, "battery_sensor_sampling_period": True},
    face.Keyboard: {"sampling_period": True},
}  # fmt: skip


def _properties(cls: type) -> dict[str, bool]:
    return {
        name: value.fset is not None
        for name, value in inspect.getmembers(cls)
        if isinstance(value, property) and not name.startswith("_")
    }


@pytest.mark.parametrize("cls", list(WEBOTS_PROPERTIES), ids=lambda c: c.__name__)
def test_properties_are_exactly_webots(cls: type) -> None:
    assert _properties(cls) == WEBOTS_PROPERTIES[cls]


def _run(controller: Path, tmp_path: Path, emu: Emulator, *extra: str) -> tuple[str, str]:
    result = subprocess.run(
        [*ego_command(), "run", "--port", emu.path, *extra, str(controller)],
        capture_output=True, text=True, cwd=tmp_path, timeout=60,
    )  # fmt: skip
    assert result.returncode == 0, result.stderr
    return result.stdout, result.stderr


def test_subclassed_robot_devices_and_keyboard_drive_the_robot(tmp_path: Path) -> None:
    with Emulator("webots", seed=3) as emu:
        start = emu.world.snapshot()
        out, err = _run(CONTROLLERS / "subclassed_devices.py", tmp_path, emu)
        end = emu.world.snapshot()
        lines = {line.split()[0]: line.split()[1:] for line in out.splitlines()}
    assert "is a Motor, not" not in err
    assert lines["front"][:2] == ["front", "front"]  # the subclass's own attribute
    assert all(float(v) >= 0 for v in lines["front"][2:])
    assert lines["light"][0] == "32" and not math.isnan(float(lines["light"][1]))
    assert float(lines["encoder"][0]) > 2.5  # 3 rad/s for a second (more if steps overran)
    assert lines["keyboard"] == ["Keys", "[]"]
    assert lines["accelerometer"] == ["32"]
    travelled = math.hypot(end.x_m - start.x_m, end.y_m - start.y_m)
    assert travelled > 0.03  # both wheels forward at 3 rad/s for a second: about 6 cm


def test_a_subclass_of_another_kind_is_refused_with_the_valid_names(tmp_path: Path) -> None:
    controller = tmp_path / "wrong_kind.py"
    controller.write_text(
        "from controller import Robot, Motor\n"
        "class WheelMotor(Motor):\n    pass\n"
        "robot = Robot()\nWheelMotor('ps0')\n"
    )
    with Emulator("webots", seed=3) as emu:
        result = subprocess.run(
            [*ego_command(), "run", "--port", emu.path, str(controller)],
            capture_output=True, text=True, cwd=tmp_path, timeout=60,
        )  # fmt: skip
    assert result.returncode != 0
    assert "'ps0' is a DistanceSensor, not a Motor" in result.stderr
    assert "left wheel motor, right wheel motor" in result.stderr


def test_every_webots_submodule_imports_with_its_names(tmp_path: Path) -> None:
    controller = tmp_path / "submodules.py"
    lines = [
        f"from controller.{module} import {', '.join(names)}"
        for module, names in WEBOTS_SUBMODULES.items()
    ]
    checks = [
        f"assert {name} is getattr(__import__('controller'), '{name}'), '{name}'"
        for names in WEBOTS_SUBMODULES.values()
        for name in names
    ]
    controller.write_text("\n".join([*lines, *checks, "print('imported', len(dir()))"]) + "\n")
    with Emulator("webots", seed=3) as emu:
        out, _ = _run(controller, tmp_path, emu)
    assert out.startswith("imported")


def test_deprecated_getters_of_absent_devices_warn_and_give_none(tmp_path: Path) -> None:
    controller = tmp_path / "deprecated.py"
    controller.write_text(
        "from controller import Robot\n"
        "robot = Robot()\n"
        "print(robot.getLightSensor('ls8'), robot.getDistanceSensor('ps12'),\n"
        "      type(robot.getDistanceSensor('ps0')).__name__)\n"
    )
    with Emulator("webots", seed=3) as emu:
        out, err = _run(controller, tmp_path, emu)
    assert out.split() == ["None", "None", "DistanceSensor"]
    assert 'Device "ls8" was not found on robot "e-puck"' in err
    assert "DEPRECATION: Robot.getLightSensor is deprecated" in err


def test_an_overrunning_loop_is_told_once_then_summarised(tmp_path: Path) -> None:
    controller = tmp_path / "overrun.py"
    controller.write_text(
        "import time\nfrom controller import Robot\nrobot = Robot()\n"
        "while robot.step(1) != -1 and robot.getTime() < 0.6:\n    time.sleep(0.002)\n"
    )
    with Emulator("webots", seed=3) as emu:
        _, err = _run(controller, tmp_path, emu)
    lines = [line for line in err.splitlines() if "overr" in line]
    assert 1 <= len(lines) <= 3, lines
    assert "overran by" in lines[0]
    assert "more overruns" in lines[-1] and "at worst" in lines[-1]


def test_the_overrun_report_says_the_first_then_one_line_a_period() -> None:
    report = OverrunReport(period_s=10.0)
    said = [report.note(t * 0.001, 1, 0.0005) for t in range(25_000)]
    lines = [line for line in said if line is not None]
    assert len(lines) == 3  # the first, then at 10 s and 20 s
    assert "overran by 0.50 ms" in lines[0]
    assert lines[1].startswith("10000 more overruns in 10.0 s")
    final = report.flush(25.0)
    assert final is not None and final.startswith("4999 more overruns")
    assert report.flush(25.0) is None


SUPERVISED_WORLD = """
[arena]
size_m = 1.0

[robot]
x_m = -0.2
y_m = 0.0
heading_deg = 0

[[box]]
x_m = 0.3
y_m = 0.3
size_m = 0.08
rgb = [200, 30, 30]
name = "TARGET"
"""


def test_a_supervisor_resets_reads_and_moves_solids_of_the_emulated_world(
    tmp_path: Path,
) -> None:
    world = tmp_path / "episodes.toml"
    world.write_text(SUPERVISED_WORLD)
    result = subprocess.run(
        [*ego_command(), "run", "--port", "sim", "--fast", "--world", str(world), "--seed", "4",
         str(CONTROLLERS / "supervisor_episodes.py")],
        capture_output=True, text=True, cwd=tmp_path, timeout=60,
    )  # fmt: skip
    assert result.returncode == 0, result.stderr
    said = {" ".join(line.split()[:2]) if line.startswith("episode") else line.split()[0]:
            line.split()[1:] for line in result.stdout.splitlines()}  # fmt: skip
    start = [float(v) for v in said["start"]]
    assert start == pytest.approx([-0.2, 0.0, 0.0, 0.0], abs=1e-9)
    assert [float(v) for v in said["target"]] == pytest.approx([0.3, 0.3, 0.025])  # 5 cm high
    assert said["missing"] == ["None"]
    for episode in ("episode 0", "episode 1"):
        _, x, y, vy = (float(v) for v in said[episode])
        # Put at (0.1, -0.2) facing +y, then 20 steps of 32 ms (virtual time: exactly) at
        # 4 rad/s: about 5 cm up +y.
        assert x == pytest.approx(0.1, abs=0.005)
        assert 0.03 < y + 0.2 < 0.08 and vy > 0.05
    first, second = ([float(v) for v in said[e][1:3]] for e in ("episode 0", "episode 1"))
    assert first == pytest.approx(second, abs=0.01)  # the same start, the same episode
    assert float(said["front"][0]) > 500  # the box it moved is right in front of ps0
    reset = [float(v) for v in said["reset"]]
    assert reset[:2] == pytest.approx([-0.2, 0.0], abs=1e-6)  # the robot back at its start
    assert reset[3:5] == pytest.approx([0.3, 0.3])  # and the box at its
    assert said["supervisor"] == ["True", "1"]


def test_on_a_real_robot_the_supervisor_says_there_is_no_simulation(tmp_path: Path) -> None:
    controller = tmp_path / "supervised.py"
    controller.write_text(
        "from controller import Supervisor\nrobot = Supervisor()\n"
        "print(robot.getSupervisor())\nrobot.getSelf()\n"
    )
    with Emulator("webots", seed=3) as emu:  # a pty: to ego, a real serial robot
        result = subprocess.run(
            [*ego_command(), "run", "--port", emu.path, str(controller)],
            capture_output=True, text=True, cwd=tmp_path, timeout=60,
        )  # fmt: skip
    assert result.returncode != 0 and result.stdout.split() == ["False"]
    assert "a real e-puck has none to supervise" in result.stderr


def test_virtual_time_moves_the_world_by_the_steps_not_the_wall_clock(tmp_path: Path) -> None:
    # Each step's work (50 ms) outlasts the step (32 ms): in real time the world would move
    # on by the wall clock; in virtual time exactly by the steps the controller took.
    controller = tmp_path / "slow_steps.py"
    controller.write_text(
        "import time\nfrom controller import Robot\nrobot = Robot()\n"
        "left, right = robot.getDevice('left wheel motor'), robot.getDevice('right wheel motor')\n"
        "sensor = robot.getDevice('left wheel sensor')\nsensor.enable(32)\n"
        "for m in (left, right):\n    m.setPosition(float('inf'))\n    m.setVelocity(3.0)\n"
        "for _ in range(25):\n    robot.step(32)\n    time.sleep(0.05)\n"
        "print(robot.getTime(), sensor.getValue())\n"
    )
    runs = {}
    for mode in ("--fast", "--no-supervised"):
        result = subprocess.run(
            [*ego_command(), "run", "--port", "sim", mode, str(controller)],
            capture_output=True, text=True, cwd=tmp_path, timeout=60,
        )  # fmt: skip
        assert result.returncode == 0, result.stderr
        runs[mode] = [float(v) for v in result.stdout.split()]
    # 24 steps of 32 ms had passed at the last read: 0.768 s in virtual time, at 3 rad/s
    # as the firmware runs it (478 steps/s, a whole number of 0.1 ms ticks a step: 500).
    # In real time the wall clock's 24 x 50 ms or more had passed.
    rate_rad_s = 10_000 / (10_000 // round(3.0 / 0.00628)) * 0.00628
    assert runs["--fast"][0] == pytest.approx(0.8)
    assert runs["--fast"][1] == pytest.approx(rate_rad_s * 0.768, rel=0.01)
    assert runs["--no-supervised"][1] > rate_rad_s * 1.2


def test_fast_is_refused_off_the_emulator(tmp_path: Path) -> None:
    controller = tmp_path / "c.py"
    controller.write_text("print('ran')\n")
    result = subprocess.run(
        [*ego_command(), "run", "--port", "/dev/ttyS0", "--fast", str(controller)],
        capture_output=True, text=True, cwd=tmp_path, timeout=60,
    )  # fmt: skip
    assert result.returncode != 0 and "ran" not in result.stdout
    assert "--fast runs the emulator in virtual time: it needs --port sim" in result.stderr
