"""``ego run --record run.mcap --record-format ros2`` on the emulator: the bag holds the
very batches and replies a JSON recording holds, ``ego replay`` feeds them to the
controller so that it reads exactly what it read on the robot, and every ROS 2 topic
decodes (rosbags' AnyReader) to the run's own samples, step by step."""

from __future__ import annotations

import json
import math
import subprocess
from collections import defaultdict
from pathlib import Path
from typing import Any

import pytest
from helpers import ego_command
from mcap.reader import make_reader
from ros2_bag_support import ir_metres, yaw
from rosbags.highlevel import AnyReader

import ego
from ego.recording.reader import Recording
from ego.recording.writer import Recorder

LOGGER = Path(__file__).parents[1] / "faces" / "controllers" / "sensor_logger.py"
#: Everything epuck_ros2 publishes that the emulated e-puck1 has, and the camera.
EVERYTHING = """
from controller import Robot
robot = Robot()
for name in [f"ps{i}" for i in range(8)] + [f"ls{i}" for i in range(8)] + [
        "gs0", "gs1", "gs2", "left wheel sensor", "right wheel sensor", "accelerometer"]:
    robot.getDevice(name).enable(32)
robot.getDevice("camera").enable(64)
left, right = robot.getDevice("left wheel motor"), robot.getDevice("right wheel motor")
for motor in (left, right):
    motor.setPosition(float("inf"))
while robot.step(32) != -1:
    near = robot.getDevice("ps0").getValue() > 150
    left.setVelocity(-3.0 if near else 4.0)
    right.setVelocity(3.0 if near else 4.0)
"""


def _ego(*args: str, cwd: Path) -> subprocess.CompletedProcess[str]:
    done = subprocess.run([*ego_command(), *args], capture_output=True, text=True, cwd=cwd,
                          timeout=120)  # fmt: skip
    assert done.returncode == 0, done.stderr
    return done


def _record(folder: Path, name: str, controller: str, *flags: str) -> Path:
    _ego("run", "--port", "sim", "--fast", "--seed", "4", "--duration", "2", "--record",
         name, *flags, controller, *(["log-" + name + ".json"] if controller == str(LOGGER)
                                     else []), cwd=folder)  # fmt: skip
    return folder / name


@pytest.fixture(scope="module")
def runs(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    folder = tmp_path_factory.mktemp("ros2runs")
    (folder / "everything.py").write_text(EVERYTHING)
    return {
        "ros2": _record(folder, "ros2.mcap", str(LOGGER), "--record-format", "ros2"),
        "all": _record(folder, "all.mcap", "everything.py", "--record-format", "ros2",
                       "--ros2-distro", "kilted"),
    }  # fmt: skip


def test_the_bag_keeps_every_batch_and_reply_a_json_recording_of_the_same_run_keeps(
    tmp_path: Path,
) -> None:
    # One robot, both recorders: each is handed the same batches (taps chain).
    plain, ros2 = Recorder(tmp_path / "plain.mcap"), Recorder(tmp_path / "ros2.mcap", "kilted")
    robot = ego.Robot("sim", seed=3)
    for recorder in (plain, ros2):
        recorder.attach(robot)
    robot.proximity.enable(32)
    robot.light.enable(64)
    robot.encoders.enable(32)
    for step in range(40):
        robot.motors.set_speed(300, -200 if step % 10 < 5 else 200)
        assert robot.step(32) == 0
    robot.close()
    plain.close()
    ros2.close()
    then, now = Recording.open(tmp_path / "plain.mcap"), Recording.open(tmp_path / "ros2.mcap")
    assert now.metadata["format"] == "ros2" and now.metadata["ros2_distro"] == "kilted"
    assert len(now.exchanges) >= 40
    assert [(e.step, e.t, e.tx, e.rx) for e in now.exchanges] == [
        (e.step, e.t, e.tx, e.rx) for e in then.exchanges
    ]
    def kept(sample: dict[str, Any]) -> dict[str, Any]:
        # Each recorder reads the wall clock and the emulator's moving world (the true
        # pose) at its own moment; everything the robot answered is the same.
        return {k: v for k, v in sample.items() if k not in ("wall_ms", "truth")}

    assert [kept(s) for s in now.samples] == [kept(s) for s in then.samples]
    assert now.robot == then.robot and now.world == then.world


def test_ego_replay_of_the_bag_answers_the_controller_exactly_as_the_robot_did(
    runs: dict[str, Path], tmp_path: Path
) -> None:
    _ego("replay", "--emulate", str(runs["ros2"]), str(LOGGER), "--", "replay.json",
         cwd=tmp_path)  # fmt: skip
    then = json.loads((runs["ros2"].parent / "log-ros2.mcap.json").read_text())
    now = json.loads((tmp_path / "replay.json").read_text())
    assert len(now) == len(then) == math.ceil(2000 / 32)
    assert now == then  # every value, every step: the same floats


def _by_time(path: Path) -> tuple[dict[int, dict[str, Any]], dict[str, list[tuple[int, Any]]]]:
    """The run's samples by log time (its /ego/sensors), and every topic's messages."""
    samples: dict[int, dict[str, Any]] = {}
    topics: dict[str, list[tuple[int, Any]]] = defaultdict(list)
    with AnyReader([path]) as reader:
        for connection, time_ns, raw in reader.messages():
            message = reader.deserialize(raw, connection.msgtype)
            if connection.topic == "/ego/sensors":
                samples[time_ns] = json.loads(message.data)
            topics[connection.topic].append((time_ns, message))
    return samples, topics


def test_every_topic_decodes_to_the_runs_own_samples_step_by_step(
    runs: dict[str, Path],
) -> None:
    samples, topics = _by_time(runs["all"])
    steps = math.ceil(2000 / 32)
    assert len(samples) == steps
    for i in range(8):
        assert len(topics[f"/ps{i}"]) == len(topics[f"/ls{i}"]) == steps
        for time_ns, message in topics[f"/ps{i}"]:
            raw = samples[time_ns]["proximity"][i]
            assert message.range == pytest.approx(ir_metres(raw), rel=1e-6, abs=1e-7)
            assert message.header.stamp.sec * 10**9 + message.header.stamp.nanosec == time_ns
        for time_ns, message in topics[f"/ls{i}"]:
            assert message.illuminance == samples[time_ns]["light"][i]
    for time_ns, message in topics["/imu"]:
        acc = message.linear_acceleration
        assert [acc.x, acc.y, acc.z] == samples[time_ns]["accelerometer"]
    for time_ns, message in topics["/joint_states"]:
        counts = samples[time_ns]["encoders"]
        assert list(message.position) == pytest.approx([c * 2 * math.pi / 1000 for c in counts])
    for time_ns, message in topics["/odom"]:
        x, y, theta = samples[time_ns]["odometry"]
        pose = message.pose.pose
        assert (pose.position.x, pose.position.y) == (x, y)
        assert yaw(pose.orientation) == pytest.approx(theta, abs=1e-9)
    speeds = {tuple(samples[t]["speed"]) for t, _ in topics["/cmd_vel"]}
    assert len(speeds) > 1  # the robot turned: the asked speeds changed
    assert len(topics["/tf"]) == len(topics["/scan"]) == len(topics["/gs0"]) == steps


def test_camera_frames_are_the_recordings_frames(runs: dict[str, Path]) -> None:
    recording = Recording.open(runs["all"])
    _, topics = _by_time(runs["all"])
    packed = topics["/image_raw/compressed"]
    assert len(recording.frames) == len(packed) == len(topics["/image_raw"]) > 10
    assert [f.jpeg for f in recording.frames] == [bytes(m.data) for _, m in packed]
    (_, first), *_ = topics["/image_raw"]
    (_, info), *_ = topics["/camera_info"]
    assert (first.width, first.height) == (info.width, info.height) == (52, 39)


def test_the_header_says_ros2_and_every_channel_is_cdr_with_a_ros2msg_schema(
    runs: dict[str, Path],
) -> None:
    with open(runs["ros2"], "rb") as file:
        reader = make_reader(file)
        assert reader.get_header().profile == "ros2"
        summary = reader.get_summary()
        assert summary is not None
    schemas = {s.name: s for s in summary.schemas.values()}
    assert all(c.message_encoding == "cdr" for c in summary.channels.values())
    assert all(s.encoding == "ros2msg" for s in schemas.values())
    text = schemas["sensor_msgs/msg/Range"].data.decode()
    assert text.startswith("uint8 ULTRASOUND=0\n")
    assert "\n" + "=" * 80 + "\nMSG: std_msgs/Header\n" in text
    topics = {c.topic for c in summary.channels.values()}
    # The logger reads ps0..ps7, the left encoder and the accelerometer: those topics,
    # ego's, and what ego derives (odometry, the asked speeds, the scan); no empty one.
    assert topics == {
        *(f"/ps{i}" for i in range(8)), "/imu", "/joint_states", "/odom", "/tf", "/scan",
        "/cmd_vel", "/tf_static", "/ego/exchange", "/ego/sensors", "/ego/log",
    }  # fmt: skip


def test_a_supervised_run_passes_the_ros2_format_to_its_controllers_process(
    tmp_path: Path,
) -> None:
    _ego("run", "--port", "sim", "--supervised", "--duration", "0.5", "--record", "s.mcap",
         "--record-format", "ros2", "--ros2-distro", "humble", str(LOGGER), "log.json",
         cwd=tmp_path)  # fmt: skip
    recording = Recording.open(tmp_path / "s.mcap")
    assert (recording.metadata["format"], recording.metadata["ros2_distro"]) == ("ros2", "humble")
    assert recording.exchanges
