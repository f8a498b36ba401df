"""ROS 2 recordings need the ros2 extra, and only they do: the recorder and the reader
load no rosbags for ego's own recordings, and a missing rosbags is one line naming the pip
command, said before any file is made. Each case runs in a fresh interpreter, rosbags
hidden by a meta-path finder so that Python raises its real ModuleNotFoundError."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
from ros2_bag_support import sample

HIDE = """
import importlib.abc, sys
class Hide(importlib.abc.MetaPathFinder):
    def find_spec(self, name, path=None, target=None):
        if name.partition(".")[0] == "rosbags":
            raise ModuleNotFoundError(f"No module named {name!r}", name=name)
        return None
sys.meta_path.insert(0, Hide())
"""


def run(code: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          timeout=120, check=False)  # fmt: skip


def test_the_recorder_and_the_reader_load_no_rosbags_for_ego_recordings() -> None:
    done = run("import sys, ego.recording.writer, ego.recording.reader, ego.app.observers\n"
               "print('rosbags' in sys.modules)")  # fmt: skip
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "False"


def test_recording_ros2_without_rosbags_is_one_line_and_no_file(tmp_path: Path) -> None:
    target = tmp_path / "run.mcap"
    done = run(HIDE + "from ego.recording.writer import Recorder\nfrom ego.errors import EgoError\n"
               f"try:\n    Recorder({str(target)!r}, ros2_distro='jazzy')\n"
               "except EgoError as exc:\n    print(exc)\n")  # fmt: skip
    assert done.returncode == 0, done.stderr
    assert done.stdout.splitlines() == ["ego.ros2 needs rosbags: pip install 'ego[ros2]'"]
    assert not target.exists()


def _ego_bag(path: Path, label: str) -> Path:
    """A Jazzy bag holding one sample on /ego/sensors, its ego metadata saying ``label``."""
    from mcap.writer import Writer

    from ego.recording.ros2_bag import Ros2Bag

    bag = Ros2Bag("jazzy")
    with open(path, "wb") as file:
        writer = Writer(file)
        writer.start(**bag.header("test"))
        bag.register(writer)
        writer.add_metadata("ego", {"format": "ros2", "ros2_distro": label})
        found = bag.ego("/ego/sensors", sample(1))
        assert found is not None
        writer.add_message(found[0], 1, found[1], 1, 1)
        writer.finish()  # type: ignore[no-untyped-call]
    return path


def test_reading_a_ros2_recording_without_rosbags_is_one_line(tmp_path: Path) -> None:
    path = _ego_bag(tmp_path / "run.mcap", "jazzy")
    done = run(HIDE + "from ego.recording.reader import Recording\n"
               "from ego.errors import EgoError\n"
               f"try:\n    Recording.open({str(path)!r})\n"
               "except EgoError as exc:\n    print(exc)\n")  # fmt: skip
    assert done.returncode == 0, done.stderr
    assert done.stdout.splitlines() == ["ego.ros2 needs rosbags: pip install 'ego[ros2]'"]
    with_rosbags = run("from ego.recording.reader import Recording\n"
                       f"print(len(Recording.open({str(path)!r}).samples))")  # fmt: skip
    assert with_rosbags.stdout.strip() == "1", with_rosbags.stderr


def test_a_bag_of_an_unknown_distribution_is_refused_in_one_line(tmp_path: Path) -> None:
    from ego.errors import RecordingError
    from ego.recording.reader import Recording

    path = _ego_bag(tmp_path / "odd.mcap", "foxy")
    with pytest.raises(RecordingError) as error:
        Recording.open(path)
    assert str(error.value) == (f"{path}: a message on /ego/sensors: ROS 2 distribution 'foxy' "
                                "is not one ego speaks (known: humble, jazzy, kilted)")  # fmt: skip
