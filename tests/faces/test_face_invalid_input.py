"""Every invalid input through the faces raises its typed error naming the valid values, and
a sensor read too early gives NaN, as in Webots (issue 3, item 7)."""

from __future__ import annotations

import math
import subprocess
from collections.abc import Callable
from pathlib import Path

import pytest

from ego import overo as ov
from ego import webots as wb
from ego.controller import DifferentialWheels
from ego.controller import Robot as WebotsRobot
from ego.errors import OutOfRangeError, PortNotFoundError, UnknownDeviceError
from ego.faces import default_robot, runtime
from ego.faces.tags import DEVICE_NAMES
from firmware_sim import Emulator

ALL_TAGS = len(DEVICE_NAMES)


# -- unknown devices and tags ------------------------------------------------------------


def test_get_device_of_an_unknown_name_warns_as_webots_and_gives_none(
    webots_robot: WebotsRobot, capsys: pytest.CaptureFixture[str]
) -> None:
    assert webots_robot.getDevice("gps") is None
    assert capsys.readouterr().err == 'Device "gps" was not found on robot "e-puck"\n'


def test_strict_get_device_of_an_unknown_name_lists_the_valid_names(
    webots_robot: WebotsRobot,
) -> None:
    webots_robot._options.strict = True  # what ego run --strict sets
    with pytest.raises(UnknownDeviceError) as info:
        webots_robot.getDevice("ps 0")
    message = str(info.value)
    assert "'ps 0'" in message
    for name in ("ps0", "ls7", "gs2", "led9", "left wheel motor", "right wheel sensor", "camera"):
        assert name in message
    assert "ps8" not in message  # not on the thesis firmware
    assert "mic0" not in message  # Webots' e-puck has no microphone device


def test_a_deprecated_getter_of_the_wrong_kind_gives_the_device_as_webots_does(
    webots_robot: WebotsRobot, capsys: pytest.CaptureFixture[str]
) -> None:
    # Webots' typed getters only call getDevice: no check of the class.
    assert type(webots_robot.getMotor("ps0")).__name__ == "DistanceSensor"
    assert webots_robot.getLED("no such led") is None
    err = capsys.readouterr().err
    assert "DEPRECATION: Robot.getMotor is deprecated" in err
    assert 'Device "no such led" was not found on robot "e-puck"' in err


def test_a_device_class_made_by_a_name_of_another_kind_lists_the_right_names(
    webots_robot: WebotsRobot,
) -> None:
    from ego.controller import LED, Motor

    with pytest.raises(UnknownDeviceError, match="'ps0' is a DistanceSensor, not a Motor") as info:
        Motor("ps0")
    assert str(info.value).endswith("valid names for a Motor: left wheel motor, right wheel motor")
    with pytest.raises(UnknownDeviceError, match="valid names for a LED: led0, led1"):
        LED("left wheel motor")


def test_the_long_range_sensors_exist_only_on_the_overo_firmware() -> None:
    with Emulator("gctronic") as emu:
        default_robot.set_options(runtime.RunOptions(port=emu.path))
        try:
            robot = WebotsRobot()
            sensor = robot.getDevice("ps9")
            sensor.enable(32)
            assert robot.step(32) == 0
            assert math.isfinite(sensor.getValue())  # type: ignore[attr-defined]
            robot.cleanup()
        finally:
            default_robot.set_options(runtime.RunOptions())


def test_wb_robot_get_device_of_an_unknown_name_lists_the_valid_names(
    face_options: runtime.RunOptions,
) -> None:
    wb.wb_robot_init()
    with pytest.raises(UnknownDeviceError, match=r"'sonar'; valid names: .*ps0, ps1, .*camera"):
        wb.wb_robot_get_device("sonar")
    with pytest.raises(UnknownDeviceError, match="'ps8'"):
        wb.wb_robot_get_device("ps8")  # a name the thesis firmware does not have


def test_a_tag_that_wb_robot_get_device_never_returns_is_refused(
    face_options: runtime.RunOptions,
) -> None:
    wb.wb_robot_init()
    for tag in (0, -1, ALL_TAGS + 1, 10_000):
        valid = rf"device tag {tag} is not one of 1\.\.{ALL_TAGS}"
        with pytest.raises(UnknownDeviceError, match=valid):
            wb.wb_distance_sensor_enable(tag, 32)
        with pytest.raises(UnknownDeviceError, match=valid):
            wb.wb_led_set(tag, 1)
        with pytest.raises(UnknownDeviceError, match=valid):
            ov.overo_light_sensors_get_value(tag)


def test_a_name_unknown_to_a_c_function_lists_the_valid_names(
    face_options: runtime.RunOptions,
) -> None:
    wb.wb_robot_init()
    with pytest.raises(UnknownDeviceError, match="'left motor'; valid names: ps0"):
        wb.wb_accelerometer_enable("left motor", 32)
    with pytest.raises(UnknownDeviceError, match="not one of accelerometer"):
        ov.overo_accelerometer_enable_raw("ps0", 32)
    with pytest.raises(UnknownDeviceError, match="not a light sensor"):
        ov.overo_light_sensors_enable(wb.wb_robot_get_device("ps0"), 32)
    with pytest.raises(UnknownDeviceError, match="mic0, mic1, mic2"):
        ov.overo_microphone_enable("led0", 32)


# -- speeds, velocities, LEDs ------------------------------------------------------------


def test_a_motor_velocity_above_6_28_is_clamped_with_webots_warning(
    webots_robot: WebotsRobot, capsys: pytest.CaptureFixture[str]
) -> None:
    motor = webots_robot.getDevice("left wheel motor")
    motor.setPosition(float("inf"))  # type: ignore[attr-defined]
    motor.setVelocity(-100.0)  # type: ignore[attr-defined]
    assert motor.getVelocity() == pytest.approx(-6.2832, abs=1e-3)  # type: ignore[attr-defined]
    assert webots_robot.core.motors.speed[0] == -1000
    assert capsys.readouterr().err == (
        'WARNING: e-puck > RotationalMotor "left wheel motor": The requested velocity -100 '
        "exceeds 'maxVelocity' = 6.28319.\n"
    )
    motor.setVelocity(float("nan"))  # type: ignore[attr-defined]
    assert "invalid 'velocity' argument (NaN)" in capsys.readouterr().err
    assert motor.getVelocity() == pytest.approx(-6.2832, abs=1e-3)  # type: ignore[attr-defined]


def test_strict_a_motor_velocity_above_6_28_is_refused(webots_robot: WebotsRobot) -> None:
    webots_robot._options.strict = True  # what ego run --strict sets
    webots_robot._devices.clear()  # views made before it keep Webots' manners
    motor = webots_robot.getDevice("left wheel motor")
    motor.setPosition(float("inf"))  # type: ignore[attr-defined]
    motor.setVelocity(1.0)  # type: ignore[attr-defined]
    for velocity in (6.3, -6.3, 100.0):
        with pytest.raises(OutOfRangeError, match=r"refused") as info:
            motor.setVelocity(velocity)  # type: ignore[attr-defined]
        assert str(velocity) in str(info.value) and "6.28" in str(info.value)
    assert motor.getVelocity() == 1.0  # type: ignore[attr-defined]
    assert webots_robot.core.motors.speed == (159, 0)  # 1 rad/s, untouched


def test_a_motor_velocity_that_is_not_a_number_is_a_type_error(webots_robot: WebotsRobot) -> None:
    motor = webots_robot.getDevice("right wheel motor")
    for velocity in ("fast", None, True):
        with pytest.raises(TypeError, match="rad/s"):
            motor.setVelocity(velocity)  # type: ignore[attr-defined]


def test_a_speed_above_1000_steps_is_refused_by_every_face(
    face_options: runtime.RunOptions,
) -> None:
    wb.wb_robot_init()
    with pytest.raises(OutOfRangeError, match=r"1001 steps/s is outside -1000\.\.1000.*refused"):
        wb.wb_differential_wheels_set_speed(1001, 0)
    with pytest.raises(OutOfRangeError, match=r"-2000 steps/s .*refused"):
        ov.overo_motors_set_speed("left wheel motor", 0, -2000)
    with pytest.raises(TypeError, match="must be a number"):
        wb.wb_differential_wheels_set_speed("full", 0)  # type: ignore[arg-type]


def test_a_differential_wheels_speed_above_1000_is_clamped_unless_strict(
    face_options: runtime.RunOptions, capsys: pytest.CaptureFixture[str]
) -> None:
    robot = DifferentialWheels()
    try:
        robot.setSpeed(1500, -1500)
        assert (robot.getLeftSpeed(), robot.getRightSpeed()) == (1000.0, -1000.0)
        assert "exceeds the maximum speed 1000" in capsys.readouterr().err
        face_options.strict = True
        with pytest.raises(OutOfRangeError, match=r"1500 steps/s is outside -1000\.\.1000"):
            robot.setSpeed(1500, 1500)
    finally:
        robot.cleanup()


def test_led_values_and_numbers_out_of_range_are_refused(
    face_options: runtime.RunOptions,
) -> None:
    wb.wb_robot_init()
    with pytest.raises(OutOfRangeError, match=r"value for led2 3 is outside 0\.\.2"):
        ov.overo_led_set("led2", 3)
    with pytest.raises(OutOfRangeError, match=r"0\.\.2"):
        ov.overo_led_set(wb.wb_robot_get_device("led2"), -1)
    with pytest.raises(UnknownDeviceError, match="led9"):
        ov.overo_led_set("led10", 1)
    with pytest.raises(TypeError, match="LED value must be an int"):
        wb.wb_led_set("led2", "on")  # type: ignore[arg-type]
    with pytest.raises(TypeError, match="LED value must be an int"):
        wb.wb_led_set("led2", 1.5)  # type: ignore[arg-type]  # C's int, unlike Python's



# -- periods and time steps --------------------------------------------------------------


PERIOD_ERROR = r"sampling period .*1\.\.86400000 ms"
TIME_STEP_ERROR = r"time step .*1\.\.86400000 ms"


BAD_PERIODS = (0, -32, 12.5)


def test_a_webots_sampling_period_that_is_not_a_positive_whole_number_is_refused(
    webots_robot: WebotsRobot,
) -> None:
    ps0 = webots_robot.getDevice("ps0")
    for period in BAD_PERIODS:
        with pytest.raises(OutOfRangeError, match=PERIOD_ERROR):
            ps0.enable(period)  # type: ignore[attr-defined]
        with pytest.raises(OutOfRangeError, match=PERIOD_ERROR):
            webots_robot.getDevice("accelerometer").enable(period)  # type: ignore[attr-defined]
    assert ps0.getSamplingPeriod() == 0  # type: ignore[attr-defined]


def test_a_c_style_sampling_period_that_is_not_a_positive_whole_number_is_refused(
    face_options: runtime.RunOptions,
) -> None:
    wb.wb_robot_init()
    for period in BAD_PERIODS:
        with pytest.raises(OutOfRangeError, match=PERIOD_ERROR):
            wb.wb_light_sensor_enable("ls0", period)  # type: ignore[arg-type]
        with pytest.raises(OutOfRangeError, match=PERIOD_ERROR):
            wb.wb_differential_wheels_enable_encoders(period)  # type: ignore[arg-type]
        with pytest.raises(OutOfRangeError, match=PERIOD_ERROR):
            ov.overo_encoders_enable("left wheel sensor", period)  # type: ignore[arg-type]
        with pytest.raises(OutOfRangeError, match=PERIOD_ERROR):
            ov.overo_microphone_enable_buffer("mic0", period)  # type: ignore[arg-type]


def test_a_time_step_that_is_not_positive_is_refused(webots_robot: WebotsRobot) -> None:
    for ms in (0, -16):
        with pytest.raises(OutOfRangeError, match=TIME_STEP_ERROR):
            webots_robot.step(ms)
    assert webots_robot.getTime() == 0.0


def test_a_c_style_time_step_that_is_not_positive_is_refused(
    face_options: runtime.RunOptions,
) -> None:
    wb.wb_robot_init()
    for ms in (0, -16):
        with pytest.raises(OutOfRangeError, match=TIME_STEP_ERROR):
            wb.wb_robot_step(ms)
        with pytest.raises(OutOfRangeError, match=TIME_STEP_ERROR):
            ov.overo_scheduler_robot_step(ms)


# -- reading too early: NaN in the faces -------------------------------------------------


def test_every_webots_sensor_reads_nan_before_it_is_enabled_and_sampled(
    face_options: runtime.RunOptions,
) -> None:
    robot = DifferentialWheels()
    try:
        ps0 = robot.getDevice("ps0")
        ls0 = robot.getDevice("ls0")
        gs0 = robot.getDevice("gs0")
        acc = robot.getDevice("accelerometer")
        wheel = robot.getDevice("left wheel sensor")
        sensors = [ps0, ls0, gs0, wheel]
        values = [s.getValue() for s in sensors]  # type: ignore[attr-defined]
        values += acc.getValues()  # type: ignore[attr-defined]
        values += [robot.getLeftEncoder(), robot.getRightEncoder()]
        for sensor in [*sensors, acc]:
            sensor.enable(32)  # type: ignore[attr-defined]
        robot.enableEncoders(32)
        values += [s.getValue() for s in sensors]  # type: ignore[attr-defined]
        values += [robot.getLeftEncoder()]
        assert all(math.isnan(v) for v in values), values

        assert robot.step(32) == 0
        assert math.isfinite(ps0.getValue())  # type: ignore[attr-defined]
        assert math.isfinite(robot.getLeftEncoder())
    finally:
        robot.cleanup()


# -- ports and files ---------------------------------------------------------------------


def test_a_missing_port_is_named_by_every_face() -> None:
    missing = "/dev/ttyEGO-not-there"
    default_robot.set_options(runtime.RunOptions(port=missing))
    try:
        with pytest.raises(PortNotFoundError, match=missing):
            WebotsRobot()
        with pytest.raises(PortNotFoundError, match=missing):
            wb.wb_robot_init()
    finally:
        default_robot.set_options(runtime.RunOptions())
    with pytest.raises(PortNotFoundError, match=missing):
        ov.overo_serial_init(230400, missing)


def test_ego_run_of_a_missing_file_exits_1_with_a_message(
    run_ego: Callable[..., subprocess.CompletedProcess[str]],
) -> None:
    done = run_ego("run", "--port", "sim", "no_such_controller.py")
    assert done.returncode == 1
    assert "no_such_controller.py" in done.stderr
    assert "does not exist" in done.stderr
    assert "Traceback" not in done.stderr


def test_ego_run_of_a_missing_port_exits_1_naming_the_port(
    run_ego: Callable[..., subprocess.CompletedProcess[str]],
) -> None:
    controller = Path(__file__).parent / "controllers" / "forever_controller.py"
    done = run_ego("run", "--port", "/dev/ttyEGO-not-there", str(controller))
    assert done.returncode == 1
    assert "/dev/ttyEGO-not-there" in done.stderr
    assert "Traceback" not in done.stderr
