"""Where no Chromium exists the browser tests skip with one reason saying how to enable
them, and EGO_REQUIRE_BROWSER=1 (CI's) turns that skip into a failure."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
#: One browser test, run in a child pytest that finds no Chromium.
BROWSER_TEST = (
    "tests/dashboard/test_dashboard_browser.py::test_an_arrow_key_drives_the_robot_in_the_world"
)


def _pytest_without_chromium(tmp_path: Path, require: bool) -> subprocess.CompletedProcess[str]:
    env = {k: v for k, v in os.environ.items() if k != "EGO_REQUIRE_BROWSER"}
    env["EGO_CHROMIUM"] = str(tmp_path / "no-such-chromium")
    if require:
        env["EGO_REQUIRE_BROWSER"] = "1"
    return subprocess.run(
        [sys.executable, "-m", "pytest", "-q", "-rsE", "-p", "no:cacheprovider", BROWSER_TEST],
        capture_output=True, text=True, cwd=ROOT, env=env, timeout=120,
    )  # fmt: skip


def test_without_chromium_a_browser_test_skips_saying_how_to_enable_it(tmp_path: Path) -> None:
    result = _pytest_without_chromium(tmp_path, require=False)
    assert result.returncode == 0, result.stdout + result.stderr
    assert "1 skipped" in result.stdout
    assert "no Chromium at" in result.stdout and "apt-get install chromium" in result.stdout


def test_ego_require_browser_turns_that_skip_into_a_failure(tmp_path: Path) -> None:
    result = _pytest_without_chromium(tmp_path, require=True)
    assert result.returncode != 0
    assert "skipped" not in result.stdout
    assert "EGO_REQUIRE_BROWSER=1: they may not skip" in result.stdout
