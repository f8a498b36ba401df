"""The ``ego`` command: the demo runs and reports (issue 3, item 8)."""

from __future__ import annotations

import re
import subprocess
from collections.abc import Callable

SUMMARY = re.compile(
    r"summary: (?P<steps>\d+) steps in (?P<time>[\d.]+) s of controller time .*"
    r"(?P<overruns>\d+) overruns, travelled (?P<travelled>[\d.]+) m, "
    r"closest approach to a wall or block (?P<closest>[\d.]+) mm"
)


def test_ego_demo_runs_and_prints_a_summary(
    run_ego: Callable[..., subprocess.CompletedProcess[str]],
) -> None:
    done = run_ego("demo", "--duration", "2")
    assert done.returncode == 0, done.stderr
    summaries = [m for line in done.stdout.splitlines() if (m := SUMMARY.search(line))]
    assert len(summaries) == 1, done.stdout
    summary = summaries[0]
    assert int(summary["steps"]) >= 2 / 0.032 - 1  # 32 ms steps for 2 s of controller time
    assert float(summary["time"]) == 2.0
    assert float(summary["travelled"]) > 0.05  # the robot drove
    assert 0.0 < float(summary["closest"]) < 500.0
    assert "motors stopped, LEDs off" in summary.string
