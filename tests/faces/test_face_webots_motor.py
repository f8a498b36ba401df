"""Webots' Motor in velocity control: ``setPosition(inf)`` then ``setVelocity(rad/s)``.

As in Webots, the velocity's sign gives the direction (the e-puck's controllers reverse a
wheel with a negative velocity), and 6.28 rad/s is 1000 steps/s.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import pytest

from ego.controller import Robot as WebotsRobot
from firmware_sim import World

INF = float("inf")


def test_a_negative_velocity_turns_the_wheel_backwards(
    webots_robot: WebotsRobot, world: World, wait_until: Callable[..., bool]
) -> None:
    left = webots_robot.getDevice("left wheel motor")
    right = webots_robot.getDevice("right wheel motor")
    left.setPosition(INF)  # type: ignore[attr-defined]
    right.setPosition(INF)  # type: ignore[attr-defined]
    left.setVelocity(-3.0)  # type: ignore[attr-defined]
    right.setVelocity(6.28)  # type: ignore[attr-defined]
    assert webots_robot.step(32) == 0
    assert wait_until(lambda: world.speeds == (-477, 999)), world.speeds

    left.setVelocity(0.0)  # type: ignore[attr-defined]
    right.setVelocity(-6.28)  # type: ignore[attr-defined]
    assert webots_robot.step(32) == 0
    assert wait_until(lambda: world.speeds == (0, -999)), world.speeds
    right.setVelocity(0.0)  # type: ignore[attr-defined]


def test_the_velocity_not_the_infinity_gives_the_direction(webots_robot: WebotsRobot) -> None:
    motor = webots_robot.getDevice("left wheel motor")
    motor.setPosition(-INF)  # type: ignore[attr-defined]
    motor.setVelocity(2.0)  # type: ignore[attr-defined]
    assert webots_robot.core.motors.speed == (318, 0)
    motor.setVelocity(-2.0)  # type: ignore[attr-defined]
    assert webots_robot.core.motors.speed == (-318, 0)
    motor.setVelocity(0.0)  # type: ignore[attr-defined]


def test_velocity_control_starts_at_the_maximum_velocity_as_in_webots(
    webots_robot: WebotsRobot,
) -> None:
    motor = webots_robot.getDevice("right wheel motor")
    assert motor.getVelocity() == pytest.approx(2 * math.pi)  # type: ignore[attr-defined]
    assert motor.getMaxVelocity() == pytest.approx(6.2832, abs=1e-4)  # type: ignore[attr-defined]
    motor.setPosition(INF)  # type: ignore[attr-defined]
    assert webots_robot.core.motors.speed == (0, 1000)
    motor.setVelocity(0.0)  # type: ignore[attr-defined]
    assert webots_robot.core.motors.speed == (0, 0)


def test_position_control_holds_still_until_the_wheel_counter_is_read(
    webots_robot: WebotsRobot,
) -> None:
    motor = webots_robot.getDevice("left wheel motor")
    motor.setPosition(1.0)  # type: ignore[attr-defined]
    assert webots_robot.core.encoders.enabled  # position control needs the counters
    assert webots_robot.core.motors.speed == (0, 0)
    assert webots_robot.step(32) == 0
    assert webots_robot.core.motors.speed[0] > 0  # now it knows where the wheel is
    motor.setPosition(INF)  # type: ignore[attr-defined]
    motor.setVelocity(0.0)  # type: ignore[attr-defined]
