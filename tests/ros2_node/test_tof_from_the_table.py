"""Issue 26, item 1: the ToF is published where the robot serves the device table's ``tof``
row (the e-puck2's DistanceSensor, in mm): the ``tof`` topic appears, reads the family
the row names, and fills the scan's middle ray (driver.cpp:443-452, :417); a robot that
does not serve it (an e-puck) gets no ``tof`` topic."""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any

import pytest

from ego.devices.table import TABLE
from ego.servers.ros2_node.build import Messages
from ego.servers.ros2_node.sampling import Sampler, served_devices
from ego.servers.ros2_node.topics import PUBLISHED, served


class FakeTof:
    """A sampled family serving ``tof``: 120 mm."""

    member_names = ("tof",)
    has_values = True
    values = (120,)

    def __init__(self) -> None:
        self.period: int | None = None

    def enable(self, period_ms: int, names: Iterable[str] | None = None) -> None:
        self.period = period_ms

    def disable(self, names: Iterable[str] | None = None) -> None:
        self.period = None

    def sampling_period(self, name: str | None = None) -> int | None:
        return self.period


class FakeRobot:
    """A robot whose only family is the ToF (the bridge asks it by the table's name), or,
    with ``tof=False``, none at all."""

    def __init__(self, tof: bool = True) -> None:
        self.tof = FakeTof()
        self.has_tof = tof

    def family(self, name: str) -> Any:
        if name != "tof" or not self.has_tof:
            from ego.errors import UnknownDeviceError

            raise UnknownDeviceError(name)
        return self.tof


def test_the_tof_topic_comes_with_the_tables_row() -> None:
    robot: Any = FakeRobot()
    assert served_devices(FakeRobot(tof=False), TABLE) == {"camera"}
    devices = served_devices(robot, TABLE)
    assert devices == {"camera", "tof"}
    names = [row.name for row in served(PUBLISHED, devices)]
    assert "tof" in names and "ps0" not in names
    sampler = Sampler(robot, {"tof"}, 64, 128, TABLE)
    sampler.enable()
    assert robot.tof.period == 64
    reading = sampler.read(5 * 10**9, wants_image=False, wants_jpeg=False)
    assert reading.tof_m == pytest.approx(0.120)
    message = Messages("jazzy").tof(reading)
    assert (message.header.frame_id, message.min_range, message.max_range) == ("tof", 0.005, 1.0)
    assert message.range == pytest.approx(0.120)
    reading.proximity = (100,) * 8
    scan = Messages("jazzy").scan(reading, 0.064)
    assert scan.ranges[10] == pytest.approx(0.120 + 0.035)
