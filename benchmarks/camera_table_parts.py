"""What the camera tables share: cells, the thesis' rows, plot styles, the C loop's names."""

from __future__ import annotations

import shutil
from typing import Any

from benchmarks.camera_convert import (
    ANCHOR,
    Timing,
)
from benchmarks.camera_measure import (
    Results,
    Rounds,
)
from benchmarks.common import Stats, fmt, thesis_csv

__all__ = [
    "C_FUSED",
    "C_TWO",
    "EGO_C_WAY",
    "MS_AXES",
    "c_skipped",
    "c_times",
    "cell",
    "curve",
    "dashed",
    "div",
    "num",
    "ref",
    "size_points",
    "solid",
    "thesis_curve",
    "thesis_rows",
]


def num(value: float) -> str:
    if value != value:
        return "-"
    size = abs(value)
    digits = 3 if size < 1 else 2 if size < 10 else 1 if size < 100 else 0
    return fmt(value, digits)


def cell(stats: Stats | None) -> str:
    """'median (min-max)' in ms."""
    if stats is None:
        return "-"
    return f"{num(stats.median)} ({num(stats.low)}-{num(stats.high)})"


def div(a: float | None, b: float | None) -> float:
    return a / b if a is not None and b else float("nan")


def thesis_rows(name: str) -> dict[int, dict[str, float]]:
    return {
        int(row["pixels"]): {k: float(v) for k, v in row.items() if k != "pixels"}
        for row in thesis_csv(name)
    }


def ref(table: dict[int, dict[str, float]], pixels: int, column: str) -> float:
    return table.get(pixels, {}).get(column, float("nan"))


def solid(color: str, marker: str = "o") -> dict[str, Any]:
    return {"color": color, "marker": marker, "linestyle": "-"}


def dashed(color: str) -> dict[str, Any]:
    return {"color": color, "marker": "x", "linestyle": "--"}


MS_AXES = {
    "xlabel": "pixels",
    "ylabel": "ego on this machine [ms] (solid, left axis)",
    "ylabel_right": "thesis on the Overo [ms] (dashed, right axis)",
}


def curve(points: list[tuple[int, float]]) -> tuple[list[int], list[float]]:
    points = sorted(p for p in points if p[1] == p[1])
    return [p[0] for p in points], [p[1] for p in points]


def size_points(by_size: dict[tuple[int, int], Rounds], name: str) -> list:
    return [(w * h, stats[name].median) for (w, h), stats in by_size.items() if name in stats]


def thesis_curve(
    thesis: dict[int, dict[str, float]], column: str, r: Results
) -> tuple[list[int], list[float]]:
    return curve([(w * h, ref(thesis, w * h, column)) for w, h in r.settings.sizes])


C_FUSED = "thesis C fused (gcc -O2)"
C_TWO = "thesis C two-pass (gcc -O2)"
EGO_C_WAY = "ego fused, the C anchor's way"


def c_times(timings: dict[str, Timing]) -> tuple[float | None, float | None]:
    fused, two = timings.get(C_FUSED), timings.get(C_TWO)
    return (fused.ms.median if fused else None, two.ms.median if two else None)


def c_skipped() -> str | None:
    """Why the thesis' C loop was not run, or None if it can be."""
    if shutil.which("gcc") is None:
        return "gcc not found on this machine"
    if not ANCHOR.is_file():
        return f"{ANCHOR} not found (../shared beside the repository)"
    return None
