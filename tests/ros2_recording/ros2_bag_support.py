"""What the ROS 2 recording tests share: expected values computed independently of
ego.recording.ros2_topics (numpy's interp over epuck_ros2's tables, written out again
here from cyberbotics/epuck_ros2@4ac67cf2 epuck_ros2_driver/src/driver.cpp), and a small
bag written from synthetic samples."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
from mcap.writer import Writer

from ego.devices.table import TABLE, DeviceTable
from ego.recording.ros2_bag import Ros2Bag

#: driver.cpp INFRARED_TABLE / GROUND_TABLE as (counts, metres), counts ascending.
IR_COUNTS = [120.0, 158.03, 234.93, 383.84, 601.46, 1465.73, 2133.33, 4095.0]
IR_METRES = [0.05, 0.04, 0.03, 0.02, 0.015, 0.01, 0.005, 0.0]


def ir_metres(raw: float) -> float:
    """driver.cpp's IR distance: the table, extrapolated linearly past either end."""
    if raw < IR_COUNTS[0]:
        slope = (IR_METRES[1] - IR_METRES[0]) / (IR_COUNTS[1] - IR_COUNTS[0])
        return IR_METRES[0] + slope * (raw - IR_COUNTS[0])
    if raw > IR_COUNTS[-1]:
        slope = (IR_METRES[-1] - IR_METRES[-2]) / (IR_COUNTS[-1] - IR_COUNTS[-2])
        return IR_METRES[-1] + slope * (raw - IR_COUNTS[-1])
    return float(np.interp(raw, IR_COUNTS, IR_METRES))


def ground_metres(raw: float) -> float:
    """GROUND_TABLE {0 m: 1000, 0.016 m: 300}: one line through both points."""
    return 0.016 * (1000.0 - raw) / 700.0


def yaw(q: Any) -> float:
    return math.atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y * q.y + q.z * q.z))


def sample(step: int, **families: Any) -> dict[str, Any]:
    """A telemetry sample as ego.core.telemetry makes one (families not given: off)."""
    base: dict[str, Any] = {
        "t": step * 0.032, "step": step, "step_ms": 32.0, "wall_ms": 32.0, "overruns": 0,
        **{f.name: None for f in TABLE.sampled}, "speed": [200, 300], "leds": [0] * 10,
        "battery": None, "odometry": [0.1, -0.2, 0.5], "odometry_source": "speeds",
        "truth": None, "camera": None,
        "link": {"batches": step, "retries": 0, "resyncs": 0, "restarts": 0},
    }  # fmt: skip
    base.update(families)
    return base


def write_bag(
    path: Path, distro: str, samples: list[dict[str, Any]], table: DeviceTable = TABLE,
    image: np.ndarray | None = None,
) -> Ros2Bag:  # fmt: skip
    """A ROS 2 recording of ``samples`` (1 s apart from t = 1 s) as the Recorder writes one."""
    from ego.camera.encode import encode_jpeg

    bag = Ros2Bag(distro, table)
    with open(path, "wb") as file:
        writer = Writer(file)
        writer.start(**bag.header("test"))
        bag.register(writer)
        sequence = 0
        times = [(i + 1) * 1_000_000_000 for i in range(len(samples))]
        for time_ns, one in zip(times, samples, strict=True):
            out = bag.step(one, time_ns)
            if image is not None:
                out += bag.frame(image, encode_jpeg(image, 90), time_ns)
            for channel, data in out:
                sequence += 1
                writer.add_message(channel, time_ns, data, time_ns, sequence)
        bag.finish(writer, path.name, times[0], times[-1])
        writer.finish()  # type: ignore[no-untyped-call]
    return bag
