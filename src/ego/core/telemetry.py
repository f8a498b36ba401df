"""What a robot did in one step, as plain data: the dashboard shows it, a recording keeps it.

:class:`Telemetry` turns a :class:`~ego.Robot` after a step into a sample, a dict of
JSON-ready values (the same keys in the dashboard's messages and in a recording's
``/ego/sensors`` channel), and keeps the odometry from the encoders. A family the
controller has not enabled (or that the firmware lacks) gives ``None``: the dashboard
says "off", a recording stores null, and nothing is ever made up.

:func:`describe_world` gives the emulator's world (walls, boxes, lamp, floor image) once,
read through its public attributes only: ego never imports the emulator.
"""

from __future__ import annotations

import base64
import time
from typing import TYPE_CHECKING, Any

import numpy as np

from ego.core.odometry import Odometry, Pose2D
from ego.errors import EgoError

if TYPE_CHECKING:
    from ego.core.channel import FirmwareInfo, LinkStats
    from ego.core.robot import Robot

__all__ = [
    "SENSOR_FAMILIES",
    "Sampler",
    "Telemetry",
    "describe_firmware",
    "describe_robot",
    "describe_world",
    "true_pose",
    "world_pose",
]

#: The families a sample holds, by Robot attribute, in the order the dashboard lists them.
SENSOR_FAMILIES = ("proximity", "light", "floor", "accelerometer", "encoders", "microphones")


def _values(family: Any) -> list[float] | None:
    """A family's last sample, or None when it has none (disabled or not served)."""
    try:
        if not family.has_values:
            return None
        return [round(float(v), 4) for v in family.values]
    except EgoError:
        return None


def _accelerometer(robot: Robot) -> list[float] | None:
    try:
        if not robot.accelerometer.has_values:
            return None
        return [round(v, 4) for v in robot.accelerometer.acceleration_mps2]
    except EgoError:  # spherical mode: no vector to draw
        return None


def world_pose(world: Any) -> list[float] | None:
    """An emulated world's ground-truth pose [x m, y m, theta rad]; None without one."""
    if world is None:
        return None
    pose = world.snapshot()
    return [round(pose.x_m, 5), round(pose.y_m, 5), round(pose.theta_rad, 5)]


def true_pose(robot: Robot) -> list[float] | None:
    """The emulator's ground-truth pose of ``robot``; None on a real robot."""
    return world_pose(getattr(robot.emulator, "world", None))


class Sampler:
    """One step's readings as a sample (the keys above), with the odometry kept across
    steps: from the encoders when they were read, else from the wheel speeds asked."""

    def __init__(self, start: list[float] | None = None) -> None:
        self.odometry = Odometry(Pose2D(*start) if start is not None else None)

    def sample(
        self, *, t_s: float, step: int, step_ms: float, wall_ms: float, overruns: int | None,
        readings: dict[str, list[float] | None], speed: list[int], leds: list[int],
        battery: int | None, truth: list[float] | None, stats: LinkStats,
        camera: list[int] | None = None,
    ) -> dict[str, Any]:  # fmt: skip
        encoders = readings.get("encoders")
        if encoders is not None:
            pose = self.odometry.from_counts(int(encoders[0]), int(encoders[1]))
        else:
            pose = self.odometry.from_speeds(speed[0], speed[1], step_ms / 1000.0)
        return {
            "t": round(t_s, 4),
            "step": step,
            "step_ms": round(step_ms, 3),
            "wall_ms": round(wall_ms, 3),
            "overruns": overruns,
            **{family: readings.get(family) for family in SENSOR_FAMILIES},
            "speed": speed,
            "leds": leds,
            "battery": battery,
            "odometry": [round(pose.x_m, 5), round(pose.y_m, 5), round(pose.theta_rad, 5)],
            "odometry_source": "encoders" if encoders is not None else "speeds",
            "truth": truth,
            "camera": camera,
            "link": {
                "batches": stats.batches,
                "retries": stats.retries,
                "resyncs": stats.resyncs,
                "restarts": stats.restarts,
            },
        }


class Telemetry:
    """Samples one robot step after step: :meth:`sample` after a step, or :meth:`track`
    when no sample is wanted (the odometry still follows every step)."""

    def __init__(self, robot: Robot) -> None:
        self.robot = robot
        self.sampler = Sampler(true_pose(robot))
        self._last_time_s = robot.time_s
        self._last_wall = time.monotonic()

    def _step_times(self) -> tuple[float, float]:
        """The last step's length in controller time and in wall time (ms)."""
        now, t = time.monotonic(), self.robot.time_s
        step_ms, wall_ms = (t - self._last_time_s) * 1000.0, (now - self._last_wall) * 1000.0
        self._last_time_s, self._last_wall = t, now
        return step_ms, wall_ms

    def track(self) -> None:
        """Follow the step in the odometry only (cheap: no sample is made)."""
        robot = self.robot
        step_ms, _ = self._step_times()
        encoders = robot.encoders
        if encoders.has_values:
            self.sampler.odometry.from_counts(*encoders.values)
        else:
            left, right = robot.motors.speed
            self.sampler.odometry.from_speeds(left, right, step_ms / 1000.0)

    def sample(self) -> dict[str, Any]:
        """The robot's state after its last step, as JSON-ready values."""
        robot = self.robot
        step_ms, wall_ms = self._step_times()
        readings = {
            family: _values(getattr(robot, family))
            for family in SENSOR_FAMILIES
            if family != "accelerometer"
        }
        readings["accelerometer"] = _accelerometer(robot)
        camera = robot.open_camera
        size = [camera.width, camera.height] if camera and camera.sampling_period else None
        return self.sampler.sample(
            t_s=robot.time_s, step=robot.steps, step_ms=step_ms, wall_ms=wall_ms,
            overruns=robot.overruns, camera=size,
            readings=readings, speed=list(robot.motors.speed),
            leds=[int(v) for v in robot.leds.values], battery=_battery(robot),
            truth=true_pose(robot), stats=robot.channel.stats,
        )  # fmt: skip


def _battery(robot: Robot) -> int | None:
    try:
        return robot.battery.raw if robot.battery.has_values else None
    except EgoError:
        return None


def describe_robot(robot: Robot) -> dict[str, Any]:
    """What does not change during a run: the robot's port, firmware and devices."""
    return describe_firmware(
        robot.channel.info, robot.port, remote=robot.remote,
        proximity_count=len(robot.proximity.member_names), led_count=len(robot.leds.values),
        families=[f for f in SENSOR_FAMILIES if getattr(robot, f).member_names],
    )  # fmt: skip


def describe_firmware(
    info: FirmwareInfo, port: str, *, remote: bool, proximity_count: int, led_count: int,
    families: list[str],
) -> dict[str, Any]:  # fmt: skip
    return {
        "port": port,
        "firmware": info.firmware.value,
        "version": info.version,
        "profile": info.profile.description,
        "remote": remote,
        "proximity_count": proximity_count,
        "led_count": led_count,
        "families": families,
    }


def describe_world(world: Any, floor_cells: int = 160) -> dict[str, Any] | None:
    """An emulated world for drawing (None: a real robot's, there is none): arena half
    extents, boxes, lamp, and the floor as a grey image ``floor_cells`` across."""
    if world is None:
        return None
    from ego.camera.encode import encode_png  # OpenCV: imported only for an emulated world

    arena = world.arena
    half_x = float(arena.half_size_m)
    half_y = float(getattr(arena, "half_y_m", None) or half_x)
    boxes = []
    for block in world.blocks:
        hx = float(block.half_size_m)
        hy = getattr(block, "half_y_m", None)
        boxes.append({
            "x": block.x_m, "y": block.y_m, "hx": hx, "hy": float(hy if hy is not None else hx),
            "yaw": float(getattr(block, "yaw_rad", 0.0)), "rgb": list(block.rgb),
        })  # fmt: skip
    cols = floor_cells
    rows = max(1, round(cols * half_y / half_x))
    xs = np.linspace(-half_x, half_x, cols)
    ys = np.linspace(half_y, -half_y, rows)  # top row is +y, as drawn from above
    grid_x, grid_y = np.meshgrid(xs, ys)
    reflectance = np.asarray(world.floor_reflectance(grid_x, grid_y), dtype=float)
    grey = np.clip(reflectance * 255, 0, 255).astype(np.uint8)
    png = encode_png(np.repeat(grey[:, :, None], 3, axis=2))
    lamp = world.lamp
    return {
        "half_x": half_x,
        "half_y": half_y,
        "boxes": boxes,
        "lamp": [float(lamp.x_m), float(lamp.y_m)],
        "floor_png": "data:image/png;base64," + base64.b64encode(png).decode("ascii"),
        "start": world_pose(world),
    }
