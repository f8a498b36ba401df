"""Recordings: ego run --record writes MCAP that the mcap reader opens with the expected
channels, one sensors message a step; replaying it into a controller gives back exactly
what the robot answered; ego plot draws it; ego replay serves it to the dashboard."""

from __future__ import annotations

import json
import math
import subprocess
from pathlib import Path

import pytest
from helpers import ego_command
from mcap.reader import make_reader
from PIL import Image

from ego.app.replay import ReplayFeed
from ego.recording.reader import Recording

LOGGER = Path(__file__).parents[1] / "faces" / "controllers" / "sensor_logger.py"


def _ego(*args: str, cwd: Path, timeout: float = 60) -> subprocess.CompletedProcess[str]:
    return subprocess.run([*ego_command(), *args], capture_output=True, text=True, cwd=cwd,
                          timeout=timeout)  # fmt: skip


@pytest.fixture(scope="module")
def recorded(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path, int]:
    """A 2 s run of the sensor logger on the emulator, recorded: (recording, log, steps)."""
    folder = tmp_path_factory.mktemp("recorded")
    run = _ego("run", "--port", "sim", "--seed", "4", "--duration", "2", "--record",
               "run.mcap", str(LOGGER), "robot.json", cwd=folder)  # fmt: skip
    assert run.returncode == 0, run.stderr
    (folder / "stderr.txt").write_text(run.stderr)  # what the run logged (its retries)
    steps = int(run.stdout.split()[-1])
    return folder / "run.mcap", folder / "robot.json", steps


def test_the_recording_opens_with_the_mcap_reader_and_holds_every_step(
    recorded: tuple[Path, Path, int],
) -> None:
    path, _, steps = recorded
    with open(path, "rb") as f:
        reader = make_reader(f)
        summary = reader.get_summary()
        assert summary is not None
        channels = {c.topic: summary.schemas[c.schema_id].name for c in summary.channels.values()}
        counts = {summary.channels[i].topic: n
                  for i, n in summary.statistics.channel_message_counts.items()}  # fmt: skip
    assert channels == {
        "/ego/sensors": "ego.Sensors",
        "/ego/exchange": "ego.Exchange",
        "/camera/image": "foxglove.CompressedImage",
        "/ego/pose/odometry": "foxglove.PoseInFrame",
        "/ego/pose/truth": "foxglove.PoseInFrame",
        "/ego/log": "foxglove.Log",
    }
    assert steps == math.ceil(2000 / 32)  # 2 s of 32 ms steps
    assert counts["/ego/sensors"] == steps
    # Every exchange is recorded: one a step, and one more for each time a step's batch
    # was asked again (an implausible reply, a restarted dsPIC: the run logs each), which
    # a loaded machine can cause (a stalled emulator's encoders leap).
    logged = (path.parent / "stderr.txt").read_text()
    retried = logged.count("; asking again") + logged.count("; re-applying the robot's state")
    assert counts["/ego/exchange"] == steps + retried, logged
    with open(path, "rb") as f:
        numbers = [json.loads(message.data)["step"] for _, _, message in
                   make_reader(f).iter_messages(topics=["/ego/exchange"])]  # fmt: skip
    assert sorted(set(numbers)) == list(range(1, steps + 1)) and numbers == sorted(numbers)
    assert counts["/ego/pose/truth"] == counts["/ego/pose/odometry"] == steps
    recording = Recording.open(path)
    assert recording.metadata["firmware"] == "webots"
    first = recording.samples[0]
    assert first["proximity"] is not None and first["encoders"] is not None
    assert recording.samples[-1]["t"] == pytest.approx(steps * 0.032)


def test_replaying_the_recording_into_the_controller_gives_exactly_what_it_read(
    recorded: tuple[Path, Path, int], tmp_path: Path
) -> None:
    path, robot_log, steps = recorded
    replay = _ego("replay", "--emulate", str(path), str(LOGGER), "--", "replay.json",
                  cwd=tmp_path)  # fmt: skip
    assert replay.returncode == 0, replay.stderr
    then = json.loads(robot_log.read_text())
    now = json.loads((tmp_path / "replay.json").read_text())
    assert len(now) == len(then) == steps
    assert now == then  # every value, every step: the same floats


def test_a_controller_that_asks_what_was_never_recorded_is_told_where(
    recorded: tuple[Path, Path, int], tmp_path: Path
) -> None:
    path, _, _ = recorded
    other = tmp_path / "light.py"
    other.write_text(
        "from controller import Robot\n"
        "robot = Robot()\n"
        "robot.getDevice('ls0').enable(32)\n"
        "while robot.step(32) != -1:\n"
        "    pass\n"
    )
    replay = _ego("replay", "--emulate", str(path), str(other), cwd=tmp_path)
    assert "at step 1 the controller asks O" in replay.stderr
    assert "cannot answer what was never recorded" in replay.stderr


def test_a_file_that_is_not_a_recording_is_refused(tmp_path: Path) -> None:
    bogus = tmp_path / "bogus.mcap"
    bogus.write_bytes(b"not mcap at all")
    result = _ego("plot", str(bogus), cwd=tmp_path)
    assert result.returncode != 0
    assert "not a readable ego recording" in result.stderr


def test_ego_plot_draws_the_sensors_the_path_and_the_timing(
    recorded: tuple[Path, Path, int], tmp_path: Path
) -> None:
    path, _, _ = recorded
    result = _ego("plot", str(path), "--out", str(tmp_path / "plots"), cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    written = [Path(line) for line in result.stdout.split()]
    assert [p.name for p in written] == ["sensors.png", "path.png", "timing.png"]
    for png in written:
        with Image.open(png) as image:
            assert image.format == "PNG" and image.width > 500
            # Not a blank canvas: the traces put many colours on it.
            assert len(image.convert("RGB").getcolors(1 << 20) or []) > 20


def test_the_replay_feed_seeks_pauses_and_changes_speed(recorded: tuple[Path, Path, int]) -> None:
    recording = Recording.open(recorded[0])
    feed = ReplayFeed(recording, playing=False)
    assert feed.hello()["mode"] == "replay" and feed.hello()["world"] is not None
    assert feed.handle("a", {"type": "replay", "action": "seek", "position": 0.5}).message is None
    state = feed.state("a")["replay"]
    assert state["t"] == pytest.approx(recording.duration_s / 2, abs=0.04)
    feed.handle("a", {"type": "replay", "action": "speed", "speed": 4})
    assert feed.state("a")["replay"]["speed"] == 4
    refused = feed.handle("a", {"type": "drive", "left": 1, "right": 1}).message
    assert refused is not None and "no robot to act on" in refused["error"]
    bad = feed.handle("a", {"type": "replay", "action": "speed", "speed": 3}).message
    assert bad is not None and "0.25, 0.5, 1.0, 2.0, 4.0" in bad["error"]
