"""Issue 33, item 4: ``imu`` carries the angular velocity where the robot has a gyro (an
e-puck2, a Pi-puck's MPU-9250 or LSM330), as epuck_ros2's driver does (driver.cpp:307-322);
a robot without one keeps the "not measured" covariance."""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any

import pytest

from ego.devices.table import TABLE
from ego.servers.ros2_node.build import Messages
from ego.servers.ros2_node.sampling import Sampler, sampled, served_devices
from ego.servers.ros2_node.topics import PUBLISHED, served


class FakeFamily:
    has_values = True

    def __init__(self, names: tuple[str, ...]) -> None:
        self.member_names = names
        self.period: int | None = None

    def enable(self, period_ms: int, names: Iterable[str] | None = None) -> None:
        self.period = period_ms

    def disable(self, names: Iterable[str] | None = None) -> None:
        self.period = None

    def sampling_period(self, name: str | None = None) -> int | None:
        return self.period


class FakeAccelerometer(FakeFamily):
    acceleration_mps2 = (0.1, 0.2, 9.81)


class FakeGyro(FakeFamily):
    rates_rad_s = (0.0, 0.0, 0.5)


class FakeRobot:
    def __init__(self, gyro: bool) -> None:
        self.accelerometer = FakeAccelerometer(("accelerometer",))
        self.gyro = FakeGyro(("gyro",) if gyro else ())

    def family(self, name: str) -> Any:
        from ego.errors import UnknownDeviceError

        if name == "accelerometer":
            return self.accelerometer
        if name == "gyro":
            return self.gyro
        raise UnknownDeviceError(name)


def _imu(robot: Any) -> Any:
    devices = served_devices(robot, TABLE)
    published = served(PUBLISHED, devices)
    assert "imu" in [row.name for row in published]
    sampler = Sampler(robot, sampled(published, devices), 64, 128, TABLE)
    sampler.enable()
    return Messages("jazzy").imu(sampler.read(10**9, wants_image=False, wants_jpeg=False))


def test_the_imu_carries_the_gyro_where_the_robot_has_one() -> None:
    robot = FakeRobot(gyro=True)
    message = _imu(robot)
    assert robot.gyro.period == 64
    assert message.angular_velocity.z == pytest.approx(0.5)
    assert list(message.angular_velocity_covariance) == [0.0] * 9


def test_without_a_gyro_the_angular_velocity_is_not_measured() -> None:
    message = _imu(FakeRobot(gyro=False))
    assert message.angular_velocity_covariance[0] == -1
