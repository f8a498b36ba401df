"""What the bridge reads of a robot after each step: one :class:`Reading`.

The sensors the published topics need are enabled at the bridge's period; the wheel
odometry is ego's (:class:`~ego.core.odometry.Odometry`, the e-puck's geometry). The
camera is captured only while a subscriber wants an image, every ``camera_period_ms``
(epuck_ros2's camera node captures only then, camera.cpp:119-124), at 160x120 unless the
robot's camera was set otherwise; a robot without a camera says so once in the log.
The ToF is read from whatever family the device table says serves the ``tof`` device,
in the units its row gives (mm, or m).
"""

from __future__ import annotations

import logging
from collections.abc import Collection, Iterable
from typing import TYPE_CHECKING

from ego.core.odometry import Odometry
from ego.devices.base import Sampled
from ego.devices.table import CAMERA, TABLE, DeviceTable
from ego.errors import CameraError, UnknownDeviceError
from ego.servers.ros2_node.reading import OdometryState, Reading

if TYPE_CHECKING:
    from ego.core.robot import Robot
    from ego.servers.ros2_node.topics import Published

__all__ = ["Sampler", "sampled", "served_devices"]

log = logging.getLogger(__name__)

#: The camera size the bridge asks for (the e-puck's sensor gives up to 640x480).
CAMERA_SIZE = (160, 120)
_ENCODERS = ("left wheel sensor", "right wheel sensor")


def served_devices(robot: Robot, table: DeviceTable = TABLE) -> set[str]:
    """The devices of ``table`` that ``robot`` serves: its family has the device among its
    members (the firmware's profile says which); the camera always (opened at need)."""
    found = set()
    for spec in table.devices:
        if spec.family == CAMERA:
            found.add(spec.name)
            continue
        try:
            family = robot.family(spec.family)
        except UnknownDeviceError:
            continue
        if spec.name in family.member_names:
            found.add(spec.name)
    return found


def sampled(published: Iterable[Published], devices: Collection[str]) -> set[str]:
    """The devices to sample for the ``published`` topics: what each needs, and the gyro
    for ``imu``'s angular velocity where the robot serves one (``devices``)."""
    needs = {n for row in published for n in row.needs}
    if "gyro" in devices and any(row.name == "imu" for row in published):
        needs.add("gyro")
    return needs


class Sampler:
    """Enables the sensors ``needs`` names and reads them into a :class:`Reading`;
    ``table`` says which family serves each (the e-puck's, or a copy with more rows)."""

    def __init__(self, robot: Robot, needs: Collection[str], period_ms: int,
                 camera_period_ms: int, table: DeviceTable = TABLE) -> None:  # fmt: skip
        self.robot = robot
        self.period_ms = period_ms
        specs = [spec for name in needs if (spec := table.find(name)) is not None]
        self.families = sorted({spec.family for spec in specs if spec.family != CAMERA})
        self.camera_every = max(1, round(camera_period_ms / period_ms))
        self.camera_ok = any(spec.family == CAMERA for spec in specs)
        #: The device table's ToF row, where the table has one and a topic needs it.
        self.tof = table.find("tof") if "tof" in needs else None
        self.odometry = Odometry()
        self._last_radians: tuple[float, float] | None = None
        self._steps = 0

    def enable(self) -> None:
        for name in self.families:
            family = self.robot.family(name)
            if isinstance(family, Sampled):
                family.enable(self.period_ms)

    def read(self, stamp_ns: int, wants_image: bool, wants_jpeg: bool) -> Reading:
        robot = self.robot
        reading = Reading(stamp_ns)
        if "proximity" in self.families and robot.proximity.has_values:
            reading.proximity = tuple(int(v) for v in robot.proximity.values[:8])
        if "light" in self.families and robot.light.has_values:
            reading.light = tuple(int(v) for v in robot.light.values[:8])
        if "floor" in self.families and robot.floor.has_values:
            reading.floor = tuple(int(v) for v in robot.floor.values[:3])
        if "accelerometer" in self.families and robot.accelerometer.has_values:
            reading.acceleration = robot.accelerometer.acceleration_mps2
        if "gyro" in self.families and robot.gyro.has_values:
            x, y, z = robot.gyro.rates_rad_s
            reading.angular_velocity = (x, y, z)
        if "encoders" in self.families and robot.encoders.has_values:
            self._wheels(reading)
        reading.tof_m = self._tof()
        self._steps += 1
        if wants_image and self.camera_ok and self._steps % self.camera_every == 0:
            self._capture(reading, wants_jpeg)
        return reading

    def _wheels(self, reading: Reading) -> None:
        left, right = self.robot.encoders.values
        radians = self.robot.encoders.radians
        last = self._last_radians or radians
        dt = self.period_ms / 1000
        speeds = ((radians[0] - last[0]) / dt, (radians[1] - last[1]) / dt)
        before = self.odometry.pose
        pose = self.odometry.from_counts(left, right)
        turn = pose.theta_rad - before.theta_rad
        forward = ((pose.x_m - before.x_m) ** 2 + (pose.y_m - before.y_m) ** 2) ** 0.5
        sign = 1.0 if speeds[0] + speeds[1] >= 0 else -1.0
        reading.wheels_rad, reading.wheels_radps = radians, speeds
        reading.odometry = OdometryState(pose.x_m, pose.y_m, pose.theta_rad,
                                         sign * forward / dt, _wrap(turn) / dt)  # fmt: skip
        self._last_radians = radians

    def _tof(self) -> float | None:
        spec = self.tof
        if spec is None:
            return None
        family = self.robot.family(spec.family)
        if not isinstance(family, Sampled) or not family.has_values:
            return None
        value = float(family.values[spec.index])  # type: ignore[attr-defined]
        return value / 1000 if spec.units == "mm" else value

    def _capture(self, reading: Reading, wants_jpeg: bool) -> None:
        try:
            camera = self.robot.camera
            if camera.frame_count == 0 and (camera.width, camera.height) == (640, 480):
                camera.set_size(*CAMERA_SIZE)
            image = camera.capture()
        except CameraError as exc:
            log.warning("no images for ROS 2: %s", exc)
            self.camera_ok = False
            return
        reading.image, reading.fov_rad = image, camera.fov_rad
        if wants_jpeg:
            from ego.camera.encode import encode_jpeg

            reading.jpeg = encode_jpeg(image, quality=80)


def _wrap(angle: float) -> float:
    import math

    return math.remainder(angle, 2 * math.pi)
