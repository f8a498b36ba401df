"""Issue 26, item 1: every topic of ``ego ros2`` on the emulator, taken by a subscriber
written as rmw_zenoh's subscription is (the exact key, the attachment required) and read
with the tests' own CDR reader, field by field against what the robot read and where the
emulator says it is.

Expected values follow cyberbotics/epuck_ros2@91ff8a1 epuck_ros2_driver/src/driver.cpp,
written here again from its lines: INFRARED_TABLE :87-88, GROUND_TABLE :89,
interpolateTable :333-350, the Range fields :432-441 (ps) and :352-365 (gs), the scan's
rays :396-428, the frames :167-235; epuck_ros2_camera/src/camera.cpp :139-167.
"""

from __future__ import annotations

import math
import struct
import threading
from collections import defaultdict
from typing import Any

import pytest
import xxhash
from helpers import wait_until
from zenoh.ext import Int64, z_deserialize

from tests.ros2_node import decode
from tests.ros2_node.bridge_support import Bridged, bridged, key_of, rgb

IR = [(0, 4095), (0.005, 2133.33), (0.01, 1465.73), (0.015, 601.46), (0.02, 383.84),
      (0.03, 234.93), (0.04, 158.03), (0.05, 120)]  # fmt: skip
GROUND = [(0, 1000), (0.016, 300)]


def f32(x: float) -> float:
    return float(struct.unpack("<f", struct.pack("<f", x))[0])


def table(value: float, rows: list[tuple[float, float]]) -> float:
    def line(v: float, x0: float, y0: float, x1: float, y1: float) -> float:
        return (y1 - y0) / (x1 - x0) * (v - x0) + y0

    for i in range(len(rows) - 1):
        (d0, r0), (d1, r1) = rows[i], rows[i + 1]
        if (r1 <= value < r0) or (r0 < value <= r1):
            return line(value, r0, d0, r1, d1)
    a, b = (rows[0], rows[1]) if value > rows[0][1] else (rows[-2], rows[-1])
    return line(value, a[1], a[0], b[1], b[0])


TOPICS = {
    **{f"ps{i}": ("sensor_msgs/msg/Range", decode.range_) for i in range(8)},
    **{f"ls{i}": ("sensor_msgs/msg/Illuminance", decode.illuminance) for i in range(8)},
    **{f"gs{i}": ("sensor_msgs/msg/Range", decode.range_) for i in range(3)},
    "scan": ("sensor_msgs/msg/LaserScan", decode.scan),
    "imu": ("sensor_msgs/msg/Imu", decode.imu),
    "odom": ("nav_msgs/msg/Odometry", decode.odometry),
    "tf": ("tf2_msgs/msg/TFMessage", decode.transforms),
    "tf_static": ("tf2_msgs/msg/TFMessage", decode.transforms),
    "joint_states": ("sensor_msgs/msg/JointState", decode.joint_states),
    "image_raw": ("sensor_msgs/msg/Image", decode.image),
    "image_raw/compressed": ("sensor_msgs/msg/CompressedImage", decode.compressed),
    "camera_info": ("sensor_msgs/msg/CameraInfo", decode.camera_info),
}


class RmwStyleSubscriptions:
    """rmw_zenoh's subscription, minus ROS: one per exact key (rmw_subscription_data.cpp:
    168), samples without an attachment dropped (:221-228), the attachment read with
    zenoh-ext's deserializer (attachment_helpers.cpp:77-82)."""

    def __init__(self, session: Any, distro: str, namespace: str = "") -> None:
        self.lock = threading.Lock()
        self.samples: dict[str, list[tuple[int, int, bytes, bytes]]] = defaultdict(list)
        self.dropped = 0
        self.subs = [
            session.declare_subscriber(key_of(f"{namespace}/{topic}", type_name, distro),
                                       self._on(topic))
            for topic, (type_name, _) in TOPICS.items()
        ]  # fmt: skip

    def _on(self, topic: str) -> Any:
        def on_sample(sample: Any) -> None:
            if sample.attachment is None:
                with self.lock:
                    self.dropped += 1
                return
            seq, stamp, gid = z_deserialize(tuple[Int64, Int64, bytes], sample.attachment)
            with self.lock:
                self.samples[topic].append((seq, stamp, gid, sample.payload.to_bytes()))

        return on_sample

    def close(self) -> None:
        for sub in self.subs:
            sub.undeclare()


def _check_range(msg: dict[str, Any], frame: str, raw: int, rows: list[Any],
                 limits: tuple[float, float], distro: str) -> None:  # fmt: skip
    assert msg["frame_id"] == frame and msg["radiation_type"] == 1  # INFRARED
    assert msg["field_of_view"] == f32(math.radians(15))
    assert (msg["min_range"], msg["max_range"]) == (f32(limits[0]), f32(limits[1]))
    assert msg["range"] == pytest.approx(table(raw, rows), rel=1e-6, abs=1e-7)
    assert ("variance" in msg) == (distro != "humble")


def _check_sensors(b: Bridged, last: dict[str, tuple[int, int, bytes, bytes]]) -> None:
    for i in range(8):
        msg = decode.range_(last[f"ps{i}"][3], b.distro)
        truth = b.truths[msg["stamp"]]
        _check_range(msg, f"ps{i}", truth.proximity[i], IR, (0.009, 0.025), b.distro)
        msg = decode.illuminance(last[f"ls{i}"][3], b.distro)
        assert (msg["frame_id"], msg["illuminance"]) == (f"ls{i}", b.truths[msg["stamp"]].light[i])
    for i in range(3):
        msg = decode.range_(last[f"gs{i}"][3], b.distro)
        truth = b.truths[msg["stamp"]]
        _check_range(msg, f"gs{i}", truth.floor[i], GROUND, (0.0, 0.016), b.distro)
    msg = decode.scan(last["scan"][3], b.distro)
    ir = [table(v, IR) for v in b.truths[msg["stamp"]].proximity]
    ir = [0.0 if d > 0.025 else d for d in ir]
    rays = {0: 3, 4: 2, 7: 1, 9: 0, 11: 7, 13: 6, 16: 5, 20: 4}
    want = [ir[rays[k]] + 0.035 if k in rays else 0.0 for k in range(21)]
    want[10] = 0.035  # the ToF's ray: an e-puck1 has none (distTof stays 0)
    assert msg["frame_id"] == "laser_scanner" and msg["ranges"] == pytest.approx(want, abs=1e-6)
    assert (msg["angle_min"], msg["angle_max"], msg["angle_increment"]) == pytest.approx(
        (math.radians(-150), math.radians(150), math.radians(15)), abs=1e-6)  # fmt: skip
    assert (msg["range_min"], msg["range_max"]) == pytest.approx((0.044, 1.035), abs=1e-6)
    msg = decode.imu(last["imu"][3], b.distro)
    assert msg["linear_acceleration"] == list(b.truths[msg["stamp"]].acceleration)
    assert msg["angular_velocity_covariance"][0] == -1  # not measured (REP-145)


def _check_motion(b: Bridged, last: dict[str, tuple[int, int, bytes, bytes]]) -> None:
    msg = decode.odometry(last["odom"][3], b.distro)
    assert (msg["frame_id"], msg["child_frame_id"]) == ("odom", "base_link")
    x, y, theta = b.relative_pose(msg["stamp"])
    assert msg["position"][:2] == pytest.approx([x, y], abs=0.01)
    qz, qw = msg["orientation"][2:]
    assert math.remainder(2 * math.atan2(qz, qw) - theta, 2 * math.pi) == pytest.approx(0, abs=0.05)
    (moved,) = decode.transforms(last["tf"][3], b.distro)
    assert (moved["frame_id"], moved["child_frame_id"]) == ("odom", "base_link")
    assert moved["translation"][:2] == pytest.approx([x, y], abs=0.01)
    statics = decode.transforms(last["tf_static"][3], b.distro)
    frames = {t["child_frame_id"]: t for t in statics}
    sensors = [f"{kind}{i}" for kind in ("ps", "ls") for i in range(8)]
    assert set(frames) == {"laser_scanner", *sensors, "gs0", "gs1", "gs2"}
    ps2 = frames["ps2"]  # -90 degrees, 35 mm from the centre (driver.cpp:185-194)
    assert ps2["translation"] == pytest.approx([0.0, -0.035, 0.0], abs=1e-9)
    msg = decode.joint_states(last["joint_states"][3], b.distro)
    assert msg["position"] == list(b.truths[msg["stamp"]].wheels_rad)


def _check_camera(b: Bridged, last: dict[str, tuple[int, int, bytes, bytes]]) -> None:
    msg = decode.image(last["image_raw"][3], b.distro)
    truth = b.truths[msg["stamp"]]
    assert truth.image is not None
    h, w = truth.image.shape[:2]
    assert (msg["frame_id"], msg["encoding"], msg["height"], msg["width"], msg["step"]) == (
        "pipuck_image_raw", "rgb8", h, w, 3 * w)  # fmt: skip
    assert msg["data"] == rgb(truth.image)
    msg = decode.compressed(last["image_raw/compressed"][3], b.distro)
    assert (msg["frame_id"], msg["format"]) == ("pipuck_image_compressed", "jpeg")
    assert msg["data"][:2] == b"\xff\xd8" and msg["stamp"] in b.truths
    info = decode.camera_info(last["camera_info"][3], b.distro)
    assert (info["height"], info["width"]) == (h, w) and info["k"][2] == w / 2


@pytest.mark.parametrize("distro", ["jazzy", "humble"])
def test_every_topic_reaches_an_rmw_style_subscriber_as_the_robot_read_it(distro: str) -> None:
    with bridged(distro) as b:
        subs = RmwStyleSubscriptions(b.ros, distro)
        b.robot.motors.set_speed(200, 100)  # moving: odometry has something to say
        try:
            assert wait_until(lambda: all(len(subs.samples[t]) >= 3 for t in TOPICS
                                          if t != "tf_static") and subs.samples["tf_static"],
                              timeout_s=20), {t: len(subs.samples[t]) for t in TOPICS}  # fmt: skip
            b.runner.close()
        finally:
            subs.close()
        with subs.lock, b.lock:
            assert subs.dropped == 0
            last = {t: s[-1] for t, s in subs.samples.items()}
            for topic, samples in subs.samples.items():
                seqs = [s[0] for s in samples]
                assert seqs == list(range(seqs[0], seqs[0] + len(seqs))), topic  # +1 each
                mangled = topic.replace("/", "%")
                token = next(k for k in b.node.token_keys
                             if f"/MP/%/%/epuck_driver/%{mangled}/" in k)  # fmt: skip
                gid = xxhash.xxh3_128_digest(token.encode())[::-1]  # low64, high64 (LE)
                assert {s[2] for s in samples} == {gid}, topic
            _check_sensors(b, last)
            _check_motion(b, last)
            _check_camera(b, last)
