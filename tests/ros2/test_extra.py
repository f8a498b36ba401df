"""The ros2 extra stays optional: ``import ego`` loads none of it, and a missing package
is one line naming the pip command. Each case runs in a fresh interpreter; the missing
package is hidden by a meta-path finder, so Python raises its real ModuleNotFoundError."""

from __future__ import annotations

import subprocess
import sys

import pytest

HIDE = """
import importlib.abc, sys
class Hide(importlib.abc.MetaPathFinder):
    def find_spec(self, name, path=None, target=None):
        if name.partition(".")[0] == {hidden!r}:
            raise ModuleNotFoundError(f"No module named {{name!r}}", name=name)
        return None
sys.meta_path.insert(0, Hide())
"""


def run(code: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, timeout=120, check=False
    )


def test_import_ego_and_ego_ros2_load_no_optional_package() -> None:
    done = run(
        "import sys, ego, ego.ros2, ego.ros2.messages, ego.ros2.gid\n"
        "print(sorted(m for m in ('rosbags', 'xxhash', 'zenoh') if m in sys.modules))"
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "[]"


@pytest.mark.parametrize(
    ("hidden", "call"),
    [
        ("rosbags", "ego.ros2.messages.type_hash('std_msgs/msg/Int32', 'jazzy')"),
        ("rosbags", "ego.ros2.messages.decode_message(b'', 'std_msgs/msg/Int32', 'kilted')"),
        ("xxhash", "ego.ros2.gid.entity_gid('@ros2_lv/0/a/0/0/NN/%/%/n', 'jazzy')"),
    ],
)
def test_a_missing_package_is_one_line_with_the_pip_command(hidden: str, call: str) -> None:
    done = run(
        HIDE.format(hidden=hidden)
        + "import ego.ros2.messages, ego.ros2.gid\nfrom ego.errors import EgoError\n"
        + f"try:\n    {call}\nexcept EgoError as exc:\n    print(type(exc).__name__, '|', exc)\n"
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout.splitlines() == [
        f"EgoError | ego.ros2 needs {hidden}: pip install 'ego[ros2]'"
    ]
