"""Hostile recordings and camera configurations are refused in bounded time and memory,
with one line naming the file and the reason (ISSUE 22 item 6).

Each file is opened in a child process (tests/hostile_files.py measures its wall time and
its peak resident memory, and kills it at a timeout), so that a bomb cannot take the test
run with it and a FIFO that hangs fails the test instead of hanging it. Before the fix a
19 KB zstd chunk decompressed to 1 GB, a 2 MB lz4 chunk to 565 MB, a FIFO hung, and
``/dev/zero`` as a camera configuration reached MemoryError at 2.2 GB.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from helpers import ego_command
from hostile_files import make, python, run_bounded

#: The budget of one refusal: generous (a child importing ego is ~30 MB, ~0.2 s), far
#: below what the hostile files cost before (1 GB and more, or a hang).
PEAK_MB = 200
WALL_S = 20
TIMEOUT_S = 60

OPEN_RECORDING = """
import sys
from ego.recording.reader import Recording
try:
    Recording.open(sys.argv[1])
except Exception as exc:
    print(f"{type(exc).__name__}: {exc}", file=sys.stderr)
    sys.exit(3)
"""

LOAD_CONFIGURATION = """
import sys
from ego.camera.config import read_configuration
try:
    read_configuration(sys.argv[1])
except Exception as exc:
    print(f"{type(exc).__name__}: {exc}", file=sys.stderr)
    sys.exit(3)
"""

CONTROLLER = "from controller import Robot\nRobot()\n"


@pytest.fixture(scope="module")
def folder(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return tmp_path_factory.mktemp("hostile")


def _refused(code: str, path: str, error: str, reason: str) -> None:
    done = run_bounded([*python(code), path], TIMEOUT_S)
    assert done.status is not None, f"{path}: still running after {TIMEOUT_S} s (a hang)"
    assert done.status == 3, f"exit {done.status}: {done.stderr[-2000:]}"
    assert done.lines == [done.lines[0]] and len(done.lines[0]) < 400, done.stderr[-2000:]
    assert done.lines[0].startswith(f"{error}: {path}: "), done.lines[0]
    assert reason in done.lines[0], done.lines[0]
    assert done.peak_mb < PEAK_MB, f"peak {done.peak_mb:.0f} MB for {path}"
    assert done.wall_s < WALL_S, f"{done.wall_s:.1f} s for {path}"


@pytest.mark.parametrize(
    ("name", "reason"),
    [
        ("zstd-bomb.mcap", "a chunk declares 1073741855 bytes uncompressed, over the 64 MiB "
                           "bound for a chunk"),
        ("zstd-liar.mcap", "a zstd chunk declares 1000 bytes uncompressed but holds more"),
        ("lz4-liar.mcap", "a lz4 chunk declares 1000 bytes uncompressed but holds more"),
        ("big-message.mcap", "a message of 20971532 bytes on /camera/image is over the 16 MiB "
                             "bound for a message"),
        ("fifo.mcap", "is a FIFO, not a regular file"),
        ("exchange-list.mcap", "message 1 on /ego/exchange: a JSON list, not an object"),
        ("exchange-no-tx.mcap", "message 1 on /ego/exchange: its tx is NoneType, not base64"),
        ("sensors-no-t.mcap", "message 1 on /ego/sensors: its t is None, not a finite number"),
        ("robot-not-json.mcap", "its robot metadata is not JSON"),
    ],
)  # fmt: skip
def test_a_hostile_recording_is_refused_in_one_line_within_budget(
    folder: Path, name: str, reason: str
) -> None:
    _refused(OPEN_RECORDING, make(folder, name), "RecordingError", reason)


@pytest.mark.parametrize(
    ("name", "reason"),
    [
        ("fifo.conf", "is a FIFO, not a regular file"),
        ("huge.conf", "314572800 bytes is over the 64 KiB bound for a camera configuration"),
        ("/dev/zero", "is a character device, not a regular file"),
    ],
)
def test_a_hostile_camera_configuration_is_refused_in_one_line_within_budget(
    folder: Path, name: str, reason: str
) -> None:
    path = name if name.startswith("/") else make(folder, name)
    _refused(LOAD_CONFIGURATION, path, "CameraConfigError", reason)


def _one_error_line(args: list[str], cwd: Path, reason: str) -> None:
    done = run_bounded([*ego_command(), *args], TIMEOUT_S, cwd=cwd)
    assert done.status is not None, f"ego {' '.join(args)}: still running after {TIMEOUT_S} s"
    assert done.status == 1, f"exit {done.status}: {done.stderr[-2000:]}"
    assert "Traceback" not in done.stderr, done.stderr[-2000:]
    assert len(done.lines) == 1, done.stderr[-2000:]
    assert done.lines[0].startswith("ego: error: ") and reason in done.lines[0], done.lines[0]
    assert done.peak_mb < PEAK_MB and done.wall_s < WALL_S, (done.peak_mb, done.wall_s)


@pytest.mark.parametrize(
    ("name", "reason"),
    [
        ("bogus-firmware.mcap", "bogus-firmware.mcap: its metadata cannot say which firmware "
                                "the robot ran: 'bogus' is not a valid Firmware"),
        ("exchange-list.mcap", "exchange-list.mcap: message 1 on /ego/exchange: a JSON list"),
        ("fifo.mcap", "fifo.mcap: is a FIFO, not a regular file"),
        ("zstd-bomb.mcap", "zstd-bomb.mcap: a chunk declares 1073741855 bytes uncompressed"),
    ],
)  # fmt: skip
def test_ego_replay_emulate_says_a_bad_recording_in_one_error_line(
    folder: Path, name: str, reason: str
) -> None:
    (folder / "ctrl.py").write_text(CONTROLLER)
    _one_error_line(["replay", "--emulate", make(folder, name), "ctrl.py"], folder, reason)


@pytest.mark.parametrize(
    ("name", "reason"),
    [
        ("no-steps.mcap", "no-steps.mcap: the recording holds no step"),
        ("sensors-no-t.mcap", "sensors-no-t.mcap: message 1 on /ego/sensors: its t is None"),
    ],
)
def test_ego_replay_says_a_bad_recording_in_one_error_line(
    folder: Path, name: str, reason: str
) -> None:
    args = ["replay", make(folder, name), "--dashboard-address", "127.0.0.1:0", "--duration", "1"]
    _one_error_line(args, folder, reason)
