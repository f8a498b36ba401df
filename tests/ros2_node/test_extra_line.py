"""Issue 26, item 1: ``ego ros2`` without one of the ros2 extra's packages says so in one
line naming the pip command (the package hidden by a meta-path finder in a fresh
interpreter, so Python raises its real ModuleNotFoundError)."""

from __future__ import annotations

import subprocess
import sys

import pytest

from tests.ros2.ros2_support import free_endpoint

HIDE = """
import importlib.abc, sys
class Hide(importlib.abc.MetaPathFinder):
    def find_spec(self, name, path=None, target=None):
        if name.partition(".")[0] == {hidden!r}:
            raise ModuleNotFoundError(f"No module named {{name!r}}", name=name)
        return None
sys.meta_path.insert(0, Hide())
from ego.app.cli import main
sys.exit(main(sys.argv[1:]))
"""


@pytest.mark.parametrize(
    ("hidden", "line"),
    [
        ("zenoh", "ego: error: ego ros2 needs eclipse-zenoh: pip install 'ego[ros2]'"),
        ("rosbags", "ego: error: ego.ros2 needs rosbags: pip install 'ego[ros2]'"),
        ("xxhash", "ego: error: ego.ros2 needs xxhash: pip install 'ego[ros2]'"),
    ],
)
def test_ego_ros2_without_a_package_says_which_in_one_line(hidden: str, line: str) -> None:
    done = subprocess.run(
        [sys.executable, "-c", HIDE.format(hidden=hidden), "ros2", "--port", "sim",
         "--router", free_endpoint(), "--duration", "0.5"],
        capture_output=True, text=True, timeout=60, check=False,
    )  # fmt: skip
    assert done.returncode == 1, done.stderr
    assert done.stderr.splitlines()[-1:] == [line], done.stderr
    assert "Traceback" not in done.stderr
