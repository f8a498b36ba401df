"""Time-step precision (thesis Tables 4.6, 4.7): share of steps within 1/5/10/20 % of the step.

A robot on the built-in emulator with nothing enabled, so each step is the scheduler
alone (as the thesis' test of its time-step function). A step's measured length is the
time between two consecutive returns of ``step()``. Conditions: single thread; a second
pure-Python thread busy; the camera capture thread busy (640x480 RGB565 -> RGB888 with
rotation, back to back).
"""

from __future__ import annotations

import random
import threading
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager

import numpy as np

from benchmarks.common import Table, progress, thesis_csv

__all__ = ["measure", "run"]

RANGES_MS = ((1, 10), (10, 100), (100, 500))
BANDS = (0.01, 0.05, 0.10, 0.20)


def _busy_python(stop: threading.Event) -> None:
    x = 0
    while not stop.is_set():
        x = (x * 31 + 7) % 1_000_003


def _busy_camera(stop: threading.Event) -> None:
    from ego.camera import rgb565_to_rgb888

    raw = np.random.default_rng(1).integers(0, 65536, 640 * 480, dtype=np.uint16).tobytes()
    while not stop.is_set():
        rgb565_to_rgb888(raw, 640, 480, rotation=180)


CONDITIONS: dict[str, Callable[[threading.Event], None] | None] = {
    "single thread": None,
    "busy Python thread": _busy_python,
    "camera thread busy": _busy_camera,
}


@contextmanager
def _background(work: Callable[[threading.Event], None] | None) -> Iterator[None]:
    if work is None:
        yield
        return
    stop = threading.Event()
    thread = threading.Thread(target=work, args=(stop,), daemon=True)
    thread.start()
    try:
        yield
    finally:
        stop.set()
        thread.join()


def measure(condition: str, lo_ms: int, hi_ms: int, samples: int, seed: int = 1) -> list[float]:
    """Relative errors |measured - asked| / asked of ``samples`` steps drawn from lo..hi ms."""
    import ego
    from ego.scheduler import tune_for_stepping

    tune_for_stepping()  # as ego run does for a controller
    rng = random.Random(seed)
    errors: list[float] = []
    with (
        ego.Robot("sim", seed=seed, handle_signals=False) as robot,
        _background(CONDITIONS[condition]),
    ):
        robot.step(lo_ms)  # anchors the clock
        last = time.perf_counter()
        for _ in range(samples):
            ms = rng.randint(lo_ms, hi_ms)
            robot.step(ms)
            now = time.perf_counter()
            errors.append(abs((now - last) * 1000.0 - ms) / ms)
            last = now
    return errors


def run(quick: bool = False) -> list[Table]:
    counts = (
        {(1, 10): 20, (10, 100): 5, (100, 500): 1}
        if quick
        else {(1, 10): 400, (10, 100): 200, (100, 500): 200}
    )
    thesis = {
        "single thread": thesis_csv("table_4_6_step_precision_single_thread.csv"),
        "busy": thesis_csv("table_4_7_step_precision_multi_thread.csv"),
    }
    tables = []
    jobs = [(c, r) for c in CONDITIONS for r in RANGES_MS]
    results: dict[tuple[str, tuple[int, int]], list[float]] = {}
    for condition, rng in progress(jobs, "step precision", total=len(jobs)):
        results[(condition, rng)] = measure(condition, rng[0], rng[1], counts[rng])
    for condition in CONDITIONS:
        ref = thesis["single thread" if condition == "single thread" else "busy"]
        ref_by_range = {row["time_range_ms"]: row for row in ref}
        table = Table(
            key=f"step_precision_{condition.replace(' ', '_')}",
            title=f"Step precision, {condition} (thesis Table "
            f"{'4.6' if condition == 'single thread' else '4.7'}): % of steps within each band",
            columns=[
                "time step [ms]",
                "steps",
                *[f"ego {int(b * 100)}%" for b in BANDS],
                *[f"thesis {int(b * 100)}%" for b in BANDS],
            ],
        )
        for rng in RANGES_MS:
            errors = results[(condition, rng)]
            label = f"{rng[0]}-{rng[1]}"
            ours = [100.0 * sum(e <= b for e in errors) / len(errors) for b in BANDS]
            theirs = ref_by_range.get(label)
            ref_values = [
                float(theirs[f"within_{int(b * 100)}pct"]) if theirs else float("nan")
                for b in BANDS
            ]
            table.rows.append([label, len(errors), *ours, *ref_values])
            table.series[label] = ours
        table.notes.append(
            "A step's length is the time between two returns of step(); "
            "the thesis ran C on a 600 MHz Cortex-A8, ego runs Python on this machine."
        )
        tables.append(table)
    return tables
