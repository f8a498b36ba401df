"""Webots' Python API beyond the e-puck's own devices: every class importable, devices the
robot lacks answered the Webots way, R2023b constructors, the Robot's other calls, and
the terminal's keyboard."""

from __future__ import annotations

import os
import pty
import select
import subprocess
from pathlib import Path

import pytest
from helpers import ego_command, wait_until

import ego.controller as controller
import ego.errors
from ego.controller import GPS, LED, Keyboard, Motor, Robot, Supervisor
from ego.controller.keyboard import decode_keys
from ego.errors import EgoError, UnknownDeviceError, UnsupportedDeviceError
from ego.faces import runtime
from firmware_sim import Emulator

CONTROLLERS = Path(__file__).parent / "controllers"

#: Every class of Webots' Python controller module (R2023b).
WEBOTS_CLASSES = [
    "Accelerometer",
    "Altimeter",
    "Brake",
    "Camera",
    "CameraRecognitionObject",
    "Compass",
    "Connector",
    "Device",
    "Display",
    "DistanceSensor",
    "Emitter",
    "Field",
    "GPS",
    "Gyro",
    "InertialUnit",
    "Joystick",
    "Keyboard",
    "LED",
    "Lidar",
    "LightSensor",
    "Motor",
    "Mouse",
    "Node",
    "Pen",
    "PositionSensor",
    "Radar",
    "RangeFinder",
    "Receiver",
    "Robot",
    "Skin",
    "Speaker",
    "Supervisor",
    "TouchSensor",
    "VacuumGripper",
]


def test_every_webots_class_can_be_imported() -> None:
    missing = [name for name in WEBOTS_CLASSES if not hasattr(controller, name)]
    assert missing == []


def test_a_device_the_epuck_lacks_is_none_and_cannot_be_made_by_name(
    face_options: runtime.RunOptions, capsys: pytest.CaptureFixture[str]
) -> None:
    robot = Robot()
    try:
        assert robot.getDevice("gps") is None
        with pytest.raises(UnknownDeviceError, match="not a GPS"):
            GPS("gps")
        assert capsys.readouterr().err.count('Device "gps" was not found on robot "e-puck"') == 2
    finally:
        robot.cleanup()


def test_r2023b_constructors_by_name_give_the_robots_devices(
    face_options: runtime.RunOptions,
) -> None:
    with pytest.raises(EgoError, match="create the Robot"):
        Motor("left wheel motor")
    robot = Robot()
    try:
        motor = Motor("left wheel motor")
        assert motor is robot.getDevice("left wheel motor")
        motor.setPosition(float("inf"))
        motor.setVelocity(2.0)
        LED("led0").set(True)
        robot.step()  # the basic time step
        assert robot.core.motors.speed[0] == 318
        assert robot.core.leds.get("led0") == 1
        with pytest.raises(UnknownDeviceError, match="is a DistanceSensor, not a Motor"):
            Motor("ps0")
    finally:
        robot.cleanup()


def test_a_second_robot_is_refused_the_webots_way(
    face_options: runtime.RunOptions, capsys: pytest.CaptureFixture[str]
) -> None:
    first = Robot()
    try:
        second = Robot()
        assert "only one Robot instance can be created" in capsys.readouterr().err
        assert second.core is first.core  # the same robot, under another name
        face_options.strict = True
        with pytest.raises(EgoError, match="only one Robot"):
            Robot()
    finally:
        first.cleanup()


def test_the_robots_other_calls_and_properties(face_options: runtime.RunOptions) -> None:
    robot = Robot()
    try:
        assert robot.getModel() == robot.model == "GCtronic e-puck"
        robot.setCustomData("lab 3")
        assert robot.getCustomData() == robot.custom_data == "lab 3"
        names = [robot.getDeviceByIndex(i).getName() for i in range(robot.getNumberOfDevices())]
        assert "ps0" in names and "left wheel motor" in names and "camera" in names
        assert robot.getSynchronization() and not robot.getSupervisor()
        robot.step(32)
        assert robot.time == robot.getTime() == pytest.approx(0.032)
        with pytest.raises(UnknownDeviceError):
            robot.getDeviceByIndex(robot.getNumberOfDevices())
    finally:
        robot.cleanup()


def test_a_supervisor_runs_the_robot_and_says_there_is_no_simulation(
    face_options: runtime.RunOptions,
) -> None:
    supervisor = Supervisor()
    try:
        assert supervisor.step(32) == 0
        with pytest.raises(UnsupportedDeviceError, match="none to supervise"):
            supervisor.getFromDef("EPUCK")
    finally:
        supervisor.cleanup()


def test_terminal_bytes_become_webots_key_codes() -> None:
    assert decode_keys(b"\x1b[A\x1b[D\x1b[5~") == [Keyboard.UP, Keyboard.LEFT, Keyboard.PAGEUP]
    assert decode_keys(b"aZ\x01 ") == [65, Keyboard.SHIFT | 90, Keyboard.CONTROL | 65, 32]


def test_keyboard_teleop_drives_the_robot_from_the_terminal(tmp_path: Path) -> None:
    """Keys typed into the terminal running ego run (a pty here) reach getKey()."""
    with Emulator("webots", seed=1) as emu:
        master, slave = pty.openpty()
        command = [
            *ego_command(),
            "run",
            "--port",
            emu.path,
            str(CONTROLLERS / "keyboard_teleop.py"),
        ]
        proc = subprocess.Popen(
            command, stdin=slave, stdout=subprocess.PIPE, text=True, cwd=tmp_path
        )
        os.close(slave)
        try:
            assert proc.stdout is not None
            assert _line(proc) == "ready"
            os.write(master, b"\x1b[A")
            assert _line(proc) == f"key {Keyboard.UP}"
            assert wait_until(lambda: emu.world.speeds == (477, 477))
            os.write(master, b"\x1b[D")
            assert _line(proc) == f"key {Keyboard.LEFT}"
            assert wait_until(lambda: emu.world.speeds == (-318, 318))
            os.write(master, b"s")
            assert _line(proc) == f"key {ord('S')}"
            os.write(master, b"q")
            assert proc.wait(timeout=15) == 0
        finally:
            if proc.poll() is None:
                proc.kill()
            os.close(master)
        assert emu.world.speeds == (0, 0)


def _line(proc: subprocess.Popen[str]) -> str:
    assert proc.stdout is not None
    ready, _, _ = select.select([proc.stdout], [], [], 15.0)
    return proc.stdout.readline().strip() if ready else ""


def test_device_calls_of_webots_with_the_epuck_protos_values(
    face_options: runtime.RunOptions,
) -> None:
    robot = Robot()
    try:
        ps0 = robot.getDevice("ps0")
        assert ps0.getType() == ps0.INFRA_RED and ps0.getAperture() == 0.1
        assert ps0.getLookupTable()[:3] == [0, 4095, 0.002] and ps0.getMinValue() == 67.19
        assert robot.getDevice("ls0").getLookupTable() == [1, 4095, 0.01, 2, 0, 0.01]
        assert robot.getDevice("accelerometer").getLookupTable()[0] == -100
        motor = robot.getDevice("left wheel motor")
        sensor = motor.getPositionSensor()
        assert sensor is robot.getDevice("left wheel sensor") and sensor.getMotor() is motor
        assert motor.getType() == motor.ROTATIONAL and motor.getBrake() is None
        assert (motor.getMinPosition(), motor.getMaxPosition()) == (0.0, 0.0)
        camera = robot.getDevice("camera")
        assert camera.getNear() == 0.0055 and not camera.hasRecognition()
        assert camera.getRecognitionObjects() == []
        ps0.enable(32)
        robot.step(32)
        assert ps0.value == ps0.getValue() and ps0.sampling_period == 32
        motor.target_velocity = 1.0
        assert motor.getVelocity() == 1.0 and motor.name == "left wheel motor"
    finally:
        robot.cleanup()


def test_node_types_are_webots_numbers(face_options: runtime.RunOptions) -> None:
    """Webots numbers node types in the order of its WbNodeType enum (R2023a on)."""
    robot = Robot()
    try:
        expected = {
            "ps0": ("DISTANCE_SENSOR", 42), "gs1": ("DISTANCE_SENSOR", 42),
            "ls3": ("LIGHT_SENSOR", 49), "accelerometer": ("ACCELEROMETER", 35),
            "left wheel motor": ("ROTATIONAL_MOTOR", 57), "led4": ("LED", 47),
            "right wheel sensor": ("POSITION_SENSOR", 52), "camera": ("CAMERA", 38),
        }  # fmt: skip
        for name, (constant, number) in expected.items():
            device = robot.getDevice(name)
            assert device.getNodeType() == getattr(controller.Node, constant) == number, name
            assert device.node_type == number
        node = controller.Node
        last = len(controller.node_types.NODE_TYPES) - 1
        assert [0, 34, last] == [node.NO_NODE, node.ROBOT, node.RADIO]
    finally:
        robot.cleanup()


def test_set_acceleration_ramps_the_speed_step_by_step(face_options: runtime.RunOptions) -> None:
    robot = Robot()
    try:
        motor = robot.getDevice("left wheel motor")
        motor.setAcceleration(31.4)  # 1 rad/s more each 32 ms step: 0 -> 6.28 in 7 steps
        motor.setPosition(float("inf"))
        motor.setVelocity(6.28)
        seen = []
        for _ in range(8):
            robot.step(32)
            seen.append(robot.core.motors.speed[0])
        assert seen[0] == 160 and seen == sorted(seen) and seen[-1] == 999  # 6.28 rad/s
        with pytest.raises(ego.errors.OutOfRangeError):
            motor.setAcceleration(0)
    finally:
        robot.cleanup()


def test_the_webots_faces_camera_is_webots_size_unless_asked(
    face_options: runtime.RunOptions,
) -> None:
    face_options.port = "sim"  # the built-in emulator, which has a rendered camera
    robot = Robot()
    try:
        camera = robot.getDevice("camera")
        assert (camera.getWidth(), camera.getHeight()) == (52, 39)
        camera.enable(32)
        robot.step(32)
        array = camera.getImageArray()
        assert len(array) == 52 and len(array[0]) == 39 and len(array[0][0]) == 3
        rgb = robot.core.camera.image
        assert array[10][20].tolist() == rgb[20, 10].tolist()  # image[x][y], as Webots
        assert array.dtype.kind == "i" and array.dtype.itemsize >= 4  # r + g + b never wraps
        assert len(camera.getImage()) == 52 * 39 * 4
    finally:
        robot.cleanup()
    face_options.camera_size = (160, 120)  # ego run --camera 160x120
    robot = Robot()
    try:
        camera = robot.getDevice("camera")
        assert (camera.getWidth(), camera.getHeight()) == (160, 120)
    finally:
        robot.cleanup()


def test_ego_run_camera_option_is_checked(tmp_path: Path) -> None:
    result = subprocess.run(
        [*ego_command(), "run", "--camera", "big", "x.py"],
        capture_output=True,
        text=True,
        cwd=tmp_path,
        timeout=30,
    )
    assert result.returncode == 2 and "WIDTHxHEIGHT" in result.stderr
