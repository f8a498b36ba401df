"""What every benchmark shares: the thesis' figures, interleaved timing, statistics, tables.

Rules (README, "Measured"): medians over repeated runs with min and max and
the count; a speed claim is a ratio measured in one run with A and B interleaved; the
thesis' figure printed beside ours with the ratio.
"""

from __future__ import annotations

import csv
import json
import statistics
import subprocess
import sys
import time
from collections.abc import Callable, Iterable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, cast

__all__ = [
    "REPO",
    "RESULTS",
    "THESIS",
    "Interrupted",
    "Stats",
    "Table",
    "emulator_process",
    "fmt",
    "interleaved",
    "progress",
    "ratio",
    "thesis_csv",
    "write_section",
]

REPO = Path(__file__).resolve().parents[1]
#: ../shared/thesis beside the repository (as in CI's checkout).
THESIS = REPO.parent / "shared" / "thesis"
RESULTS = REPO / "benchmarks" / "results"


def thesis_csv(name: str) -> list[dict[str, str]]:
    """Rows of one of the thesis' tables, or [] when ../shared is not beside the repo."""
    path = THESIS / name
    if not path.is_file():
        return []
    with path.open(newline="") as f:
        return list(csv.DictReader(f))


@dataclass(frozen=True)
class Stats:
    """Median, min and max of repeated measurements (seconds or any unit), and their count."""

    median: float
    low: float
    high: float
    n: int

    @classmethod
    def of(cls, values: Sequence[float]) -> Stats:
        return cls(statistics.median(values), min(values), max(values), len(values))

    def scaled(self, k: float) -> Stats:
        return Stats(self.median * k, self.low * k, self.high * k, self.n)


def interleaved(
    contenders: dict[str, Callable[[], object]], repeats: int, inner: int = 1
) -> dict[str, Stats]:
    """Time each contender ``repeats`` times, A B C A B C..., a sample the mean of ``inner`` calls.

    Interleaving makes the ratios fair on a shared machine: a slow moment hits everyone.
    """
    samples: dict[str, list[float]] = {name: [] for name in contenders}
    for fn in contenders.values():  # warm-up: caches, lazy allocations, JIT-free but fair
        fn()
    for _ in range(repeats):
        for name, fn in contenders.items():
            t0 = time.perf_counter()
            for _ in range(inner):
                fn()
            samples[name].append((time.perf_counter() - t0) / inner)
    return {name: Stats.of(values) for name, values in samples.items()}


class Interrupted(KeyboardInterrupt):
    """Ctrl-C inside a section, carrying the tables built from the part that finished."""

    def __init__(self, tables: list[Table]) -> None:
        super().__init__()
        self.tables = tables


def ratio(a: float, b: float) -> float:
    return a / b if b else float("nan")


def fmt(value: float | str | None, digits: int = 2) -> str:
    if value is None:
        return "-"
    if isinstance(value, str):
        return value
    if value != value:  # NaN
        return "-"
    if isinstance(value, int):
        return f"{value:,}".replace(",", "'")
    return f"{value:,.{digits}f}".replace(",", "'")


@dataclass
class Table:
    """One reproduced table: printed to the terminal, written as Markdown and CSV."""

    key: str
    title: str
    columns: list[str]
    rows: list[list[Any]] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    #: Free data for plots (lists of numbers keyed by series name).
    series: dict[str, Any] = field(default_factory=dict)

    def markdown(self) -> str:
        lines = [f"### {self.title}", ""]
        lines.append("| " + " | ".join(self.columns) + " |")
        lines.append("| " + " | ".join("---" for _ in self.columns) + " |")
        for row in self.rows:
            lines.append(
                "| " + " | ".join(fmt(c) if not isinstance(c, str) else c for c in row) + " |"
            )
        if self.notes:
            lines.append("")
            lines.extend(self.notes)
        return "\n".join(lines) + "\n"

    def write_csv(self, folder: Path) -> Path:
        folder.mkdir(parents=True, exist_ok=True)
        path = folder / f"{self.key}.csv"
        with path.open("w", newline="") as f:
            writer = csv.writer(f)
            writer.writerow(self.columns)
            for row in self.rows:
                writer.writerow([c if isinstance(c, str) else f"{c:.6g}" for c in row])
        return path

    def print(self) -> None:
        widths = [
            max(len(str(c)), *(len(_cell(r[i])) for r in self.rows)) if self.rows else len(str(c))
            for i, c in enumerate(self.columns)
        ]
        print(f"\n{self.title}")
        print("  ".join(str(c).rjust(w) for c, w in zip(self.columns, widths, strict=True)))
        for row in self.rows:
            print("  ".join(_cell(c).rjust(w) for c, w in zip(row, widths, strict=True)))
        for note in self.notes:
            print(note)


def _cell(value: Any) -> str:
    return value if isinstance(value, str) else fmt(value)


def progress(items: Iterable[Any], desc: str, total: int | None = None) -> Iterator[Any]:
    """A progress bar on stderr when it is a terminal (tqdm when installed, else a counter).

    Not on a terminal (a log file, CI), nothing: ``python -m benchmarks`` prints one line
    per section there instead of thousands of carriage-return fragments.
    """
    try:
        from tqdm import tqdm
    except ImportError:
        yield from _plain_progress(items, desc, total)
        return
    # disable=None: tqdm turns itself off when stderr is not a terminal.
    yield from tqdm(items, desc=desc, total=total, leave=False, dynamic_ncols=True, disable=None)


def _plain_progress(items: Iterable[Any], desc: str, total: int | None) -> Iterator[Any]:
    import sys

    if not sys.stderr.isatty():
        yield from items
        return
    for i, item in enumerate(items, 1):
        if total:
            sys.stderr.write(f"\r{desc}: {i}/{total}")
            sys.stderr.flush()
        yield item
    if total:
        sys.stderr.write("\r" + " " * (len(desc) + 20) + "\r")


#: The thesis measured the Overo line at 230400 baud with the command set of Table 4.1
#: (the one Webots' firmware serves, M included); the emulator carries it at that rate.
THESIS_LINE_BAUD = 230400



@contextmanager
def emulator_process(*flags: str) -> Iterator[str]:
    """``python -m firmware_sim`` at the thesis' baud (seed 1) in its own process; yields
    its pty (or its URL, with ``--wifi``).

    In its own process so that the client's CPU time (``time.process_time``) and its GIL
    are its own, and every client measured meets the same emulator.
    """
    proc = subprocess.Popen(
        [sys.executable, "-m", "firmware_sim", "--baud", str(THESIS_LINE_BAUD), "--seed", "1",
         *flags],
        stdout=subprocess.PIPE,
        text=True,
        cwd=REPO,  # never src/ego, where ego/serial would shadow pyserial
    )  # fmt: skip
    try:
        assert proc.stdout is not None
        path = proc.stdout.readline().strip()
        if not path:
            raise RuntimeError("the emulator printed no pty path")
        yield path
    finally:
        proc.terminate()
        proc.wait(timeout=10)
        if proc.stdout is not None:
            proc.stdout.close()


def write_section(
    path: Path, markers: tuple[str, str], body: Sequence[str], *, after: str = "",
    heading: str = "",
) -> None:
    """Put ``body`` (Markdown blocks) between the ``markers`` (begin, end) in ``path``: in
    place of the section already there, else right after the marker ``after`` when the
    file has it, else at the end (a missing file starts as ``heading``)."""
    begin, end = markers
    section = "\n".join([begin, *body, end])
    text = path.read_text() if path.exists() else heading
    if begin in text:
        head, rest = text.split(begin, 1)
        text = head + section + rest.split(end, 1)[1]
    elif after and after in text:
        head, sep, rest = text.partition(after)
        text = head + sep + "\n\n" + section + rest
    else:
        text = text.rstrip("\n") + "\n\n" + section + "\n"
    path.write_text(text)


def print_and_save(tables: list[Table], quick: bool) -> Path:
    """Print each table and write its CSV; the folder they went to (quick runs apart)."""
    folder = RESULTS / "quick" if quick else RESULTS
    for table in tables:
        table.print()
        table.write_csv(folder)
    return folder


def interleaved_rounds(
    contenders: dict[str, Callable[[], float]], rounds: int
) -> dict[str, list[float]]:
    """Each contender's measure, ``rounds`` times, contenders alternating round by round
    (so that a slow moment of the machine hits every one alike)."""
    measured: dict[str, list[float]] = {name: [] for name in contenders}
    for _ in range(rounds):
        for name, measure in contenders.items():
            measured[name].append(measure())
    return measured


def ratio_rows(
    measured: dict[str, list[float]], reference: str, scale: float = 1e6
) -> list[list[Any]]:
    """Rows of (name, median x scale, median / the reference's median)."""
    base = statistics.median(measured[reference])
    return [
        [name, statistics.median(values) * scale, statistics.median(values) / base]
        for name, values in measured.items()
    ]


def section_main(run: Callable[[bool], list[Table]], doc: str | None) -> Callable[[], int]:
    """A benchmark module's ``main``: ``--quick`` for a smoke run; print and save."""

    def main(argv: list[str] | None = None) -> int:
        import argparse

        parser = argparse.ArgumentParser(description=(doc or "").splitlines()[0])
        parser.add_argument("--quick", action="store_true", help="a smoke run: small counts")
        args = parser.parse_args(argv)
        print_and_save(run(args.quick), args.quick)
        return 0

    return main


def rss_kb() -> int:
    """This process' resident memory now (VmRSS, kB)."""
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1])
    raise RuntimeError("no VmRSS in /proc/self/status")


def flood_result(process: subprocess.Popen[str], timeout_s: float = 60.0) -> dict[str, float]:
    """What a flooder process printed last as a JSON line when it ended (killed if it
    outlives ``timeout_s``); {} if it printed none (the Zenoh and ROS 2 floods')."""
    try:
        out, _ = process.communicate(timeout=timeout_s)
    except subprocess.TimeoutExpired:
        process.kill()
        out, _ = process.communicate()
    lines = [line for line in out.splitlines() if line.startswith("{")]
    return cast(dict[str, float], json.loads(lines[-1])) if lines else {}
