"""What a robot did in one step, as plain data: the dashboard shows it, a recording keeps it.

:class:`Telemetry` turns a :class:`~ego.Robot` after a step into a sample, a dict of
JSON-ready values (the same keys in the dashboard's messages and in a recording's
``/ego/sensors`` channel), and keeps the odometry from the encoders. A family the
controller has not enabled (or that the firmware lacks) gives ``None``: the dashboard
says "off", a recording stores null, and nothing is ever made up.

The families a sample holds, and how the page and the plots show them, are the device
table's (:data:`ego.devices.table.TABLE`: its families with a ``Series``); each family
says what it shows (``Device.readings``). A table may be handed in instead (a test's copy).

:func:`describe_world` gives the emulator's world (walls, boxes, lamp, floor image) once,
read through the typed ground truth (:mod:`ego.core.ground_truth`): ego never imports the
emulator.
"""

from __future__ import annotations

import base64
import time
from typing import TYPE_CHECKING, Any

import numpy as np

from ego.core.odometry import Odometry, Pose2D
from ego.devices.table import TABLE, DeviceTable
from ego.errors import EgoError

if TYPE_CHECKING:
    from ego.core.ground_truth import GroundTruth
    from ego.core.robot import Robot
    from ego.seam.channel import FirmwareInfo, LinkStats

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

#: The families a sample holds, by Robot attribute, in the order the dashboard lists them:
#: the device table's.
SENSOR_FAMILIES: tuple[str, ...] = tuple(f.name for f in TABLE.sampled)


def _readings(robot: Robot, family: str) -> list[float] | None:
    """A family's last sample, or None when it has none (disabled or not served)."""
    try:
        values = robot.family(family).readings()
    except EgoError:
        return None
    return None if values is None else [round(float(v), 4) for v in values]


def world_pose(truth: GroundTruth | None) -> list[float] | None:
    """A simulated robot's ground-truth pose [x m, y m, theta rad]; None without one."""
    pose = truth.pose() if truth is not None else None
    return None if pose is None else pose.rounded()


def true_pose(robot: Robot) -> list[float] | None:
    """The emulator's ground-truth pose of ``robot``; None on a real robot."""
    return world_pose(robot.ground_truth)


class Sampler:
    """One step's readings as a sample (the keys above), with the odometry kept across
    steps: from the encoders when they were read, else from the wheel speeds asked."""

    def __init__(self, start: list[float] | None = None, table: DeviceTable = TABLE) -> None:
        self.odometry = Odometry(Pose2D(*start) if start is not None else None)
        #: The families a sample holds readings of (the table's, in its order).
        self.families = tuple(f.name for f in table.sampled)

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
            **{family: readings.get(family) for family in self.families},
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

    def __init__(self, robot: Robot, table: DeviceTable = TABLE) -> None:
        self.robot = robot
        self.sampler = Sampler(true_pose(robot), table)
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
        readings = {family: _readings(robot, family) for family in self.sampler.families}
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


def describe_robot(robot: Robot, table: DeviceTable = TABLE) -> dict[str, Any]:
    """What does not change during a run: the robot's port, firmware and devices."""
    served = {type(family).table_family for family in robot.families if family.member_names}
    return describe_firmware(
        robot.channel.info, robot.port, remote=robot.remote,
        proximity_count=len(robot.proximity.member_names), led_count=len(robot.leds.values),
        families=[f.name for f in table.sampled if f.name in served], table=table,
    )  # fmt: skip


def describe_firmware(
    info: FirmwareInfo, port: str, *, remote: bool, proximity_count: int, led_count: int,
    families: list[str], table: DeviceTable = TABLE,
) -> dict[str, Any]:  # fmt: skip
    """The robot as the page is first told it; ``series``: how it draws each family the
    table samples (the page hard-codes none)."""
    return {
        "port": port,
        "firmware": info.firmware.value,
        "version": info.version,
        "profile": info.profile.description,
        "remote": remote,
        "proximity_count": proximity_count,
        "led_count": led_count,
        # The LEDs whose value is a colour 0xRRGGBB (the e-puck2's led1, 3, 5, 7).
        "rgb_leds": list(info.profile.rgb_leds),
        "families": families,
        "series": table.describe_series(),
    }


def describe_world(truth: GroundTruth | None, floor_cells: int = 160) -> dict[str, Any] | None:
    """A simulated world for drawing (None: a real robot's, there is none): arena half
    extents, boxes, lamp, and the floor as a grey image ``floor_cells`` across."""
    world = truth.true_world if truth is not None else None
    if truth is None or world is None:
        return None
    from ego.camera.encode import encode_png  # OpenCV: imported only for an emulated world

    layout = world.layout()
    half_x, half_y = float(layout.half_x_m), float(layout.half_y_m)
    boxes = [
        {"x": box.x_m, "y": box.y_m, "hx": float(box.half_x_m), "hy": float(box.half_y_m),
         "yaw": float(box.yaw_rad), "rgb": list(box.rgb)}
        for box in layout.boxes
    ]  # fmt: skip
    cols = floor_cells
    rows = max(1, round(cols * half_y / half_x))
    xs = np.linspace(-half_x, half_x, cols)
    ys = np.linspace(half_y, -half_y, rows)  # top row is +y, as drawn from above
    grid_x, grid_y = np.meshgrid(xs, ys)
    reflectance = np.asarray(world.floor_reflectance(grid_x, grid_y), dtype=float)
    grey = np.clip(reflectance * 255, 0, 255).astype(np.uint8)
    png = encode_png(np.repeat(grey[:, :, None], 3, axis=2))
    return {
        "half_x": half_x,
        "half_y": half_y,
        "boxes": boxes,
        "lamp": [float(layout.lamp_m[0]), float(layout.lamp_m[1])],
        "floor_png": "data:image/png;base64," + base64.b64encode(png).decode("ascii"),
        "start": world_pose(truth),
    }
