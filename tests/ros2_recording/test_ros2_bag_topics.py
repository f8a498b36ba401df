"""A ROS 2 recording, written from synthetic samples: every supported distribution's bag
opens with rosbags' reader and with mcap-ros2-support's decoder (which parses the
``ros2msg`` schema text itself), its fields are epuck_ros2's conversions of the samples,
its header, channels and metadata are rosbag2's, and a family the device table gains
gets its topic with no edit to the recording code."""

from __future__ import annotations

import math
from collections import defaultdict
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from mcap.reader import make_reader
from mcap_ros2.decoder import DecoderFactory
from ros2_bag_support import ground_metres, ir_metres, sample, write_bag, yaw
from rosbags.highlevel import AnyReader
from ruamel.yaml import YAML

from ego.devices.table import TABLE
from ego.errors import UnknownDeviceError
from ego.recording.ros2_bag import Ros2Bag
from ego.ros2.messages import type_hash

DISTROS = ("humble", "jazzy", "kilted")
PROXIMITY = [4000.0, 2500.0, 700.0, 300.0, 150.0, 100.0, 2000.0, 1200.0]
LIGHT = [3300.0, 3310.0, 200.0, 4000.0, 0.0, 12.0, 3000.0, 3500.0]
SAMPLES = [
    sample(1, proximity=PROXIMITY, light=LIGHT, floor=[900.0, 500.0, 300.0],
           accelerometer=[0.1, -0.2, 9.8], encoders=[100.0, -250.0]),
    sample(2, proximity=[v + 10 for v in PROXIMITY], light=None, floor=None,
           accelerometer=None, encoders=[110.0, -240.0], speed=[-100, 100],
           odometry=[0.0, 0.0, -1.0]),
]  # fmt: skip
IMAGE = np.dstack([np.full((6, 8), c, dtype=np.uint8) for c in (200, 100, 50)])


def read_all(path: Path) -> dict[str, list[tuple[int, Any]]]:
    """Every topic's (log time, message), decoded by rosbags' AnyReader."""
    found: dict[str, list[tuple[int, Any]]] = defaultdict(list)
    with AnyReader([path]) as reader:
        for connection, time_ns, raw in reader.messages():
            found[connection.topic].append((time_ns, reader.deserialize(raw, connection.msgtype)))
    return found


@pytest.fixture(params=DISTROS)
def bag(request: pytest.FixtureRequest, tmp_path: Path) -> tuple[str, Path]:
    path = tmp_path / f"{request.param}.mcap"
    write_bag(path, request.param, SAMPLES, image=IMAGE)
    return request.param, path


def test_rosbags_reads_every_topic_and_each_field_is_epuck_ros2s_conversion(
    bag: tuple[str, Path],
) -> None:
    _, path = bag
    found = read_all(path)
    for i in range(8):
        (t1, first), (_, second) = found[f"/ps{i}"]
        assert t1 == 1_000_000_000 and first.header.frame_id == f"ps{i}"
        assert first.range == pytest.approx(ir_metres(PROXIMITY[i]), rel=1e-6, abs=1e-7)
        assert second.range == pytest.approx(ir_metres(PROXIMITY[i] + 10), rel=1e-6, abs=1e-7)
        assert (first.min_range, first.max_range) == pytest.approx((0.009, 0.025))
        assert first.field_of_view == pytest.approx(math.radians(15))
        assert first.radiation_type == 1  # INFRARED
        ((_, light),) = found[f"/ls{i}"]  # step 2 had the light off: no message
        assert light.illuminance == LIGHT[i]
    for i, raw in enumerate([900.0, 500.0, 300.0]):
        ((_, ground),) = found[f"/gs{i}"]
        assert ground.range == pytest.approx(ground_metres(raw), abs=1e-7)
        assert ground.max_range == pytest.approx(0.016)
    ((_, imu),) = found["/imu"]
    acc = imu.linear_acceleration
    assert [acc.x, acc.y, acc.z] == [0.1, -0.2, 9.8]
    assert imu.orientation_covariance[0] == -1.0  # REP-145: no orientation
    joints = [m for _, m in found["/joint_states"]]
    assert joints[0].name == ["left wheel sensor", "right wheel sensor"]
    assert list(joints[1].position) == pytest.approx([110 * 2 * math.pi / 1000,
                                                      -240 * 2 * math.pi / 1000])  # fmt: skip


def test_odometry_tf_and_cmd_vel_are_the_samples_pose_and_wheel_speeds(
    bag: tuple[str, Path],
) -> None:
    _, path = bag
    found = read_all(path)
    metres_per_step = 2 * math.pi * 0.0205 / 1000
    for (_, odom), (_, tf), (_, twist), one in zip(
        found["/odom"], found["/tf"], found["/cmd_vel"], SAMPLES, strict=True
    ):
        x, y, theta = one["odometry"]
        pose = odom.pose.pose
        assert (pose.position.x, pose.position.y) == (x, y)
        assert yaw(pose.orientation) == pytest.approx(theta)
        assert (odom.header.frame_id, odom.child_frame_id) == ("odom", "base_link")
        (moved,) = tf.transforms
        assert (moved.header.frame_id, moved.child_frame_id) == ("odom", "base_link")
        assert (moved.transform.translation.x, moved.transform.translation.y) == (x, y)
        left, right = one["speed"]
        assert twist.linear.x == pytest.approx((left + right) / 2 * metres_per_step)
        assert twist.angular.z == pytest.approx((right - left) * metres_per_step / 0.052)
        assert odom.twist.twist.linear.x == twist.linear.x


def test_the_scan_is_built_from_the_ir_sensors_as_epuck_ros2_builds_it(
    bag: tuple[str, Path],
) -> None:
    _, path = bag
    (_, scan), _ = read_all(path)["/scan"]
    assert len(scan.ranges) == 21
    assert scan.angle_min == pytest.approx(math.radians(-150))
    assert scan.angle_increment == pytest.approx(math.radians(15))
    rays = {3: 0, 2: 4, 1: 7, 0: 9, 7: 11, 6: 13, 5: 16, 4: 20}  # sensor -> ray, driver.cpp
    for sensor, ray in rays.items():
        metres = ir_metres(PROXIMITY[sensor])
        expected = (0.0 if metres > 0.025 else metres) + 0.035
        assert scan.ranges[ray] == pytest.approx(expected, abs=1e-6), sensor
    assert scan.ranges[10] == pytest.approx(0.035)  # no ToF on an e-puck1: 0 + 0.035
    assert all(scan.ranges[r] == 0.0 for r in set(range(21)) - {*rays.values(), 10})


def test_the_camera_frame_is_image_compressed_image_and_camera_info(
    bag: tuple[str, Path],
) -> None:
    import cv2

    _, path = bag
    found = read_all(path)
    (_, raw), _ = found["/image_raw"]
    assert (raw.height, raw.width, raw.encoding, raw.step) == (6, 8, "rgb8", 24)
    assert np.array_equal(np.asarray(raw.data).reshape(6, 8, 3), IMAGE)
    (_, packed), _ = found["/image_raw/compressed"]
    assert packed.format == "jpeg"
    decoded = cv2.imdecode(np.asarray(packed.data), cv2.IMREAD_COLOR)[:, :, ::-1]
    assert np.abs(decoded.astype(int) - IMAGE).max() <= 3
    (_, info), _ = found["/camera_info"]
    assert (info.height, info.width, info.header.frame_id) == (6, 8, "camera")


def test_mcap_ros2_support_decodes_every_message_from_the_schema_text_alone(
    bag: tuple[str, Path],
) -> None:
    distro, path = bag
    counts: dict[str, int] = defaultdict(int)
    with open(path, "rb") as file:
        reader = make_reader(file, decoder_factories=[DecoderFactory()])
        assert reader.get_header().profile == "ros2"
        for schema, channel, _, decoded in reader.iter_decoded_messages():
            assert (schema.encoding, channel.message_encoding) == ("ros2msg", "cdr")
            counts[channel.topic] += 1
            if channel.topic == "/ps2" and counts["/ps2"] == 1:
                assert decoded.range == pytest.approx(ir_metres(PROXIMITY[2]), rel=1e-6)
                assert hasattr(decoded, "variance") == (distro != "humble")
    assert counts["/ps0"] == 2 and counts["/ls0"] == 1 and counts["/image_raw"] == 2


def test_channels_carry_rosbag2s_metadata_and_the_bag_its_rosbag2_record(
    bag: tuple[str, Path],
) -> None:
    distro, path = bag
    with open(path, "rb") as file:
        reader = make_reader(file)
        summary = reader.get_summary()
        assert summary is not None
        records = {m.name: m.metadata for m in reader.iter_metadata()}
    total = sum(summary.statistics.channel_message_counts.values())
    yaml = YAML(typ="safe")
    for channel in summary.channels.values():
        type_name = summary.schemas[channel.schema_id].name
        (qos,) = yaml.load(channel.metadata["offered_qos_profiles"])
        assert qos["depth"] == (100 if channel.topic == "/tf" else 10 if "/ego/" in channel.topic
                                else 1)  # fmt: skip
        expected_hash = "" if distro == "humble" else type_hash(type_name, distro)
        assert channel.metadata["topic_type_hash"] == expected_hash
        # Humble's rosbag2 reads the numeric QoS form; Jazzy's and Kilted's the named one.
        assert qos["reliability"] == (1 if distro == "humble" else "reliable")
    if distro == "humble":  # Humble's storage writes the distribution, and reads nothing
        assert records["rosbag2"] == {"ROS_DISTRO": "humble"}
        return
    info = yaml.load(records["rosbag2"]["serialized_metadata"])
    assert info["version"] == 9 and info["storage_identifier"] == "mcap"
    # Every field Jazzy's decoder reads for version 9, of the kind it reads it as
    # (ros2/rosbag2@64717ee8 rosbag2_storage/include/rosbag2_storage/yaml.hpp:277-307).
    assert isinstance(info["custom_data"], dict) and info["compression_format"] == ""
    assert info["relative_file_paths"] == [path.name]
    assert isinstance(info["duration"]["nanoseconds"], int)
    assert isinstance(info["starting_time"]["nanoseconds_since_epoch"], int)
    (one_file,) = info["files"]
    assert one_file["message_count"] == total and one_file["path"] == path.name
    assert info["message_count"] == total and info["ros_distro"] == distro
    topics = {t["topic_metadata"]["name"]: t for t in info["topics_with_message_count"]}
    assert topics["/ps0"]["message_count"] == 2
    assert topics["/ps0"]["topic_metadata"]["type_description_hash"] == type_hash(
        "sensor_msgs/msg/Range", distro)


def test_humbles_range_has_no_variance_field_in_its_schema_or_payload(tmp_path: Path) -> None:
    sizes = {}
    for distro in ("humble", "jazzy"):
        path = tmp_path / f"{distro}.mcap"
        write_bag(path, distro, SAMPLES[:1])
        with open(path, "rb") as file:
            reader = make_reader(file)
            for schema, _channel, message in reader.iter_messages(topics=["/ps0"]):
                sizes[distro] = len(message.data)
                assert ("float32 variance" in schema.data.decode()) == (distro == "jazzy")
    assert sizes["jazzy"] - sizes["humble"] == 4


def test_a_family_the_table_gains_appears_with_its_topic(tmp_path: Path) -> None:
    # The e-puck2's ToF row as issue 25 adds it (a DistanceSensor in mm; added here unless
    # the table has it already), and a gyro in rad/s, a family no table has yet.
    epuck2 = frozenset({"webots"})
    rows = [("rate gyro", "rate_gyro", 0, "Gyro", "rad/s", epuck2)]
    if TABLE.find("tof") is None:
        rows.append(("tof", "tof", 0, "DistanceSensor", "mm", epuck2))
        assert "/tof" not in Ros2Bag("jazzy").channels
    table = TABLE.extended(rows=rows)
    path = tmp_path / "e2.mcap"
    readings = {"tof": [123.0], "rate_gyro": [0.5, -1.0, 2.0]}
    bag = write_bag(path, "jazzy", [{**SAMPLES[0], **readings}], table)
    assert "/tof" in bag.registered
    found = read_all(path)
    ((_, tof),) = found["/tof"]
    assert tof.range == pytest.approx(0.123) and tof.max_range == pytest.approx(1.0)
    assert tof.field_of_view == pytest.approx(math.radians(25))
    ((_, imu),) = found["/imu"]
    rate = imu.angular_velocity
    assert [rate.x, rate.y, rate.z] == [0.5, -1.0, 2.0]
    assert imu.angular_velocity_covariance[0] == 0.0  # known now, not REP-145's -1
    ((_, scan),) = found["/scan"]
    assert scan.ranges[10] == pytest.approx(0.123 + 0.035)  # the 0° ray is the ToF's
    ((_, static),) = found["/tf_static"]
    tof_frame = next(t for t in static.transforms if t.child_frame_id == "tof")
    assert tof_frame.transform.translation.x == pytest.approx(0.035)


def test_a_topic_gets_its_channel_with_its_first_message_only(tmp_path: Path) -> None:
    bag = write_bag(tmp_path / "few.mcap", "jazzy", [sample(1, light=LIGHT)])
    assert set(bag.registered) == {*(f"/ls{i}" for i in range(8)), "/cmd_vel", "/odom", "/tf",
                                   "/tf_static", "/ego/sensors", "/ego/exchange",
                                   "/ego/log"}  # fmt: skip
    with AnyReader([tmp_path / "few.mcap"]) as reader:
        assert sorted(c.topic for c in reader.connections) == sorted(bag.registered)


def test_an_unknown_distribution_is_one_line_listing_the_known_ones() -> None:
    with pytest.raises(UnknownDeviceError) as error:
        Ros2Bag("rolling")
    assert str(error.value) == (
        "ROS 2 distribution 'rolling' is not one ego speaks (known: humble, jazzy, kilted)"
    )


def test_tf_static_places_the_sensors_frames_once_as_epuck_ros2_does(
    bag: tuple[str, Path],
) -> None:
    distro, path = bag
    ((_, static),) = read_all(path)["/tf_static"]  # one message, with the first step
    frames = {t.child_frame_id: t for t in static.transforms}
    tof = {"tof"} if TABLE.find("tof") is not None else set()  # the e-puck2's, once merged
    assert set(frames) == {"laser_scanner", *(f"ps{i}" for i in range(8)),
                           *(f"ls{i}" for i in range(8)), "gs0", "gs1", "gs2", *tof}  # fmt: skip
    assert all(t.header.frame_id == "base_link" for t in static.transforms)
    ps2 = frames["ps2"].transform  # driver.cpp: -90°, 0.035 m from the centre
    assert (ps2.translation.x, ps2.translation.y) == pytest.approx((0.0, -0.035), abs=1e-12)
    assert yaw(ps2.rotation) == pytest.approx(math.radians(-90))
    gs1 = frames["gs1"].transform.translation
    assert (gs1.x, gs1.y) == pytest.approx((0.03, 0.0))
    with open(path, "rb") as file:
        summary = make_reader(file).get_summary()
    assert summary is not None
    (channel,) = [c for c in summary.channels.values() if c.topic == "/tf_static"]
    (qos,) = YAML(typ="safe").load(channel.metadata["offered_qos_profiles"])
    # tf2_ros's static broadcaster offers transient local, so late joiners get it.
    assert qos["durability"] == (1 if distro == "humble" else "transient_local")
