"""Startup: what ``import ego`` and a controller's ``from controller import Robot`` cost.

Each statement runs in a fresh interpreter under ``python -X importtime``; a sample is
one run, and the table gives the best (minimum) over the runs, as startup is a fixed
cost that a busy machine only adds to, and the median beside it: the whole import's
wall time and the *self* time of ego's own modules (their bodies, not what they
import), numpy's, and everyone else's. ``python -c pass`` is the floor.

Bytecode matters: with ``PYTHONDONTWRITEBYTECODE`` set (as on the machine the issue was
measured on) and an editable install, Python compiles every ego module from source on
every start, which roughly triples ego's self time (31 ms against 10 ms there). These
rows run with ego's bytecode written once beforehand (``compileall``), as an installed
package has it.
"""

from __future__ import annotations

import compileall
import os
import re
import statistics
import subprocess
import sys
from dataclasses import dataclass

import ego
from benchmarks.common import Table, fmt

__all__ = ["ImportTimes", "measure", "run"]

STATEMENTS = {
    "python -c pass": "pass",
    "import ego": "import ego",
    # What `ego run` makes `from controller import Robot` resolve to.
    "from controller import Robot": "from ego.controller import Robot",
}
_LINE = re.compile(r"import time:\s+(\d+) \|\s+(\d+) \| (\s*)(\S+)")


@dataclass(frozen=True)
class ImportTimes:
    """One run's import times in ms: the whole, and self time by owner."""

    total: float
    ego: float
    numpy: float
    other: float
    modules: int


def parse_importtime(stderr: str) -> ImportTimes:
    """Sum ``-X importtime``'s self column by top-level package (ms)."""
    by_owner = {"ego": 0, "numpy": 0, "other": 0}
    total = modules = 0
    for match in _LINE.finditer(stderr):
        self_us, cumulative, indent, name = int(match[1]), int(match[2]), match[3], match[4]
        top = name.split(".")[0]
        by_owner[top if top in by_owner else "other"] += self_us
        modules += 1
        if not indent:
            total += cumulative
    return ImportTimes(
        total / 1e3,
        by_owner["ego"] / 1e3,
        by_owner["numpy"] / 1e3,
        by_owner["other"] / 1e3,
        modules,
    )


def measure(statement: str, runs: int) -> list[ImportTimes]:
    """``runs`` fresh interpreters importing ``statement``."""
    results = []
    for _ in range(runs):
        done = subprocess.run(
            [sys.executable, "-X", "importtime", "-c", statement],
            capture_output=True,
            text=True,
            check=True,
        )
        results.append(parse_importtime(done.stderr))
    return results


def _compile_ego() -> None:
    """Write ego's bytecode once (what pip does at install), so no run compiles it."""
    compileall.compile_dir(os.path.dirname(ego.__file__), quiet=2)


def run(quick: bool = False) -> list[Table]:
    runs = 2 if quick else 21
    _compile_ego()
    table = Table(
        key="startup_imports",
        title="Startup: import times in a fresh interpreter (ms, best of runs)",
        columns=[
            "statement",
            "wall ms",
            "ego self ms",
            "ego self median",
            "numpy self ms",
            "other self ms",
            "modules",
            "runs",
        ],
    )
    for name, statement in STATEMENTS.items():
        times = measure(statement, runs)
        table.rows.append(
            [
                name,
                min(t.total for t in times),
                min(t.ego for t in times),
                statistics.median(t.ego for t in times),
                min(t.numpy for t in times),
                min(t.other for t in times),
                fmt(int(statistics.median(t.modules for t in times))),
                str(runs),
            ]
        )
    table.notes.append(
        "ego self: the summed self time of ego's own modules (issue 27's target: 15 ms or "
        "less). `from controller import Robot` is timed as `from ego.controller import "
        "Robot`, what `ego run` resolves it to; a controller's face loads numpy for its "
        "camera and sensor arrays, `import ego` does not."
    )
    return [table]


if __name__ == "__main__":
    for t in run(quick="--quick" in sys.argv):
        t.print()
