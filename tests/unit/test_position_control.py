"""Position control (ego.devices.position_control), sans-I/O, and the Webots Motor using it."""

from __future__ import annotations

import math

import pytest

from ego.controller import Robot as WebotsRobot
from ego.devices.motors import MAX_SPEED_RAD_S
from ego.devices.position_control import (
    GAIN_PER_S,
    TOLERANCE_RAD,
    position_speed,
    position_speed_rad_s,
)
from ego.faces.runtime import RunOptions


def test_far_from_the_target_the_wheel_turns_at_the_set_velocity() -> None:
    assert position_speed_rad_s(10.0, 0.0, 3.0) == 3.0
    assert position_speed_rad_s(-10.0, 0.0, 3.0) == -3.0
    assert position_speed_rad_s(-10.0, 0.0, -3.0) == -3.0  # the target gives the direction


def test_near_the_target_the_speed_is_proportional_to_the_distance() -> None:
    assert position_speed_rad_s(1.1, 1.0, MAX_SPEED_RAD_S) == pytest.approx(GAIN_PER_S * 0.1)
    assert position_speed_rad_s(0.9, 1.0, MAX_SPEED_RAD_S) == pytest.approx(-GAIN_PER_S * 0.1)


def test_within_one_step_of_the_target_the_wheel_stops() -> None:
    assert math.isclose(TOLERANCE_RAD, 2 * math.pi / 1000)
    assert position_speed_rad_s(1.0 + TOLERANCE_RAD / 2, 1.0, 6.0) == 0.0
    assert position_speed_rad_s(1.0 + TOLERANCE_RAD * 2, 1.0, 6.0) != 0.0


def test_position_speed_is_in_whole_steps_per_second() -> None:
    assert position_speed(100.0, 0.0, MAX_SPEED_RAD_S) == 1000
    assert position_speed(0.0, 100.0, math.pi) == -500
    assert position_speed(0.0, 0.0, math.pi) == 0


def test_the_webots_motor_drives_at_the_cores_position_speed() -> None:
    """After each step the Motor sends what position_speed gives for the wheel's angle."""
    robot = WebotsRobot(options=RunOptions(port="sim", seed=1, basic_time_step_ms=16))
    try:
        motor = robot.getMotor("right wheel motor")
        motor.setVelocity(2.0)
        motor.setPosition(1.5)
        assert robot.core.encoders.sampling_period() == 16  # the robot's basic time step
        speeds = []
        for _ in range(40):
            assert robot.step(16) == 0
            current = robot.core.encoders.radians[1]
            assert robot.core.motors.speed[1] == position_speed(1.5, current, 2.0)
            speeds.append(robot.core.motors.speed[1])
        # Far from 1.5 rad it turns at the set 2 rad/s; as it nears the target it slows.
        assert speeds[0] == position_speed(1.5, 0.0, 2.0) > 0
        assert min(speeds) < speeds[0]
    finally:
        robot.cleanup()
