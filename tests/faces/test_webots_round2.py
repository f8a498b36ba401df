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
from ego.overrun_report import OverrunReport
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
    assert 2.5 < float(lines["encoder"][0]) < 3.5  # 3 rad/s for about a second
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
