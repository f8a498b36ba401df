"""Time-step precision (thesis Tables 4.6, 4.7): share of steps within 1/5/10/20 % of the step.

A robot on the built-in emulator with nothing enabled, so each step is the scheduler
alone (as the thesis' test of its time-step function). A step's measured length is the
time between two consecutive returns of ``step()``. Conditions: single thread; a second
pure-Python thread busy; the camera capture thread busy (640x480 RGB565 -> RGB888 with
rotation, back to back).
"""

from __future__ import annotations

import os
import random
import subprocess
import sys
import threading
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass

import numpy as np

from benchmarks.common import Table, progress, thesis_csv
from ego.nursery import Nursery

__all__ = [
    "attribution_table",
    "fixed_steps",
    "machine_figures",
    "measure",
    "measure_ranges",
    "run",
]

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
    with Nursery("the benchmark's background work") as threads:
        threads.start_thread(work, stop, name="bench-background")
        try:
            yield
        finally:
            stop.set()


def measure(condition: str, lo_ms: int, hi_ms: int, samples: int, seed: int = 1) -> list[float]:
    """Relative errors |measured - asked| / asked of ``samples`` steps drawn from lo..hi ms."""
    return measure_ranges(condition, {(lo_ms, hi_ms): samples}, seed)[(lo_ms, hi_ms)]


def measure_ranges(
    condition: str, samples: dict[tuple[int, int], int], seed: int = 1
) -> dict[tuple[int, int], list[float]]:
    """:func:`measure` for each range, on one robot and one background load."""
    import ego
    from ego.core.scheduler import tune_for_stepping

    tune_for_stepping()  # as ego run does for a controller
    results: dict[tuple[int, int], list[float]] = {}
    with (
        ego.Robot("sim", seed=seed, handle_signals=False) as robot,
        _background(CONDITIONS[condition]),
    ):
        for (lo_ms, hi_ms), count in samples.items():
            rng = random.Random(seed)
            errors = results[(lo_ms, hi_ms)] = []
            robot.step(lo_ms)  # anchors the clock
            last = time.perf_counter()
            for _ in range(count):
                ms = rng.randint(lo_ms, hi_ms)
                robot.step(ms)
                now = time.perf_counter()
                errors.append(abs((now - last) * 1000.0 - ms) / ms)
                last = now
    return results


def run(quick: bool = False) -> list[Table]:
    counts = (
        {(1, 10): 10, (10, 100): 3, (100, 500): 1}
        if quick
        else {(1, 10): 400, (10, 100): 200, (100, 500): 200}
    )
    thesis = {
        "single thread": thesis_csv("table_4_6_step_precision_single_thread.csv"),
        "busy": thesis_csv("table_4_7_step_precision_multi_thread.csv"),
    }
    tables = []
    results: dict[tuple[str, tuple[int, int]], list[float]] = {}
    for condition in progress(CONDITIONS, "step precision", total=len(CONDITIONS)):
        for rng, errors in measure_ranges(condition, counts).items():
            results[(condition, rng)] = errors
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
    if quick:
        few = tuple(ATTRIBUTION[i] for i in (0, 4, 6, 9))
        tables.append(attribution_table(10, (5,), few, machine_s=0.2))
    else:
        tables.append(attribution_table(200))
    return tables


# -- where the misses come from ------------------------------------------------------------

_BUSY_PROCESS = (
    "while True:\n    x = 0\n    for i in range(10**6):\n        x = (x * 31 + 7) % 1_000_003\n"
)


def _busy_process(stop: threading.Event) -> None:
    """The same pure-Python loop, but in another process: CPU load without the GIL."""
    child = subprocess.Popen([sys.executable, "-c", _BUSY_PROCESS])
    try:
        stop.wait()
    finally:
        child.kill()
        child.wait()


@dataclass(frozen=True)
class Condition:
    """A load, the switch interval (None: ego run's 0.2 ms), and the stepper's policy."""

    label: str
    work: Callable[[threading.Event], None] | None
    interval: float | None = None
    realtime: bool = False


ATTRIBUTION = (
    Condition("single thread", None),
    Condition("busy process (CPU load, no GIL)", _busy_process),
    Condition("busy Python thread, switch interval 5 ms (Python's default)", _busy_python, 0.005),
    Condition("busy Python thread, 1 ms", _busy_python, 0.001),
    Condition("busy Python thread, 0.2 ms (ego run)", _busy_python),
    Condition("busy Python thread, 0.05 ms", _busy_python, 0.00005),
    Condition("camera thread busy, 0.2 ms (ego run)", _busy_camera),
    Condition("single thread, stepper SCHED_FIFO", None, realtime=True),
    Condition("busy process, stepper SCHED_FIFO", _busy_process, realtime=True),
    Condition("busy Python thread, 0.2 ms, stepper SCHED_FIFO", _busy_python, realtime=True),
    Condition("camera thread busy, 0.2 ms, stepper SCHED_FIFO", _busy_camera, realtime=True),
)


@contextmanager
def _realtime(wanted: bool) -> Iterator[bool]:
    """The calling thread on SCHED_FIFO (priority 10) meanwhile, if wanted and allowed."""
    if not wanted:
        yield False
        return
    try:
        os.sched_setscheduler(0, os.SCHED_FIFO, os.sched_param(10))
    except (OSError, AttributeError):  # not permitted here: say so in the table
        yield False
        return
    try:
        yield True
    finally:
        os.sched_setscheduler(0, os.SCHED_OTHER, os.sched_param(0))


@contextmanager
def _switch_interval(seconds: float | None) -> Iterator[None]:
    previous = sys.getswitchinterval()
    if seconds is not None:
        sys.setswitchinterval(seconds)
    try:
        yield
    finally:
        sys.setswitchinterval(previous)


def fixed_steps(condition: Condition, ms: int, n: int) -> list[float] | None:
    """Signed lateness (ms) of ``n`` steps of ``ms`` on the emulator under ``condition``;
    None if it asks for SCHED_FIFO and this machine does not allow it."""
    import ego
    from ego.core.scheduler import tune_for_stepping

    tune_for_stepping()
    late: list[float] = []
    with (
        _switch_interval(condition.interval),
        ego.Robot("sim", seed=1, handle_signals=False) as robot,
        _background(condition.work),
        _realtime(condition.realtime) as realtime,  # after the other threads: not inherited
    ):
        if condition.realtime and not realtime:
            return None
        robot.step(ms)
        last = time.perf_counter()
        for _ in range(n):
            robot.step(ms)
            now = time.perf_counter()
            late.append((now - last) * 1000.0 - ms)
            last = now
    return late


def machine_figures(seconds: float) -> dict[str, float]:
    """What the machine itself does to a lone thread: sleep overshoot and preemptions.

    ``sleep 1 ms overshoot``: time.sleep(0.001) (with ego's 1 us timer slack) minus 1 ms.
    ``preempted``: a tight loop reading the clock for ``seconds``; every gap above 50 us
    is time the kernel gave the CPU to someone else (other processes: the machine's load).
    """
    from ego.core.scheduler import tune_for_stepping

    tune_for_stepping()
    overshoot = []
    for _ in range(int(seconds * 500)):
        t0 = time.perf_counter()
        time.sleep(0.001)
        overshoot.append((time.perf_counter() - t0 - 0.001) * 1e3)
    overshoot.sort()
    gaps = []
    end = time.perf_counter() + seconds
    last = time.perf_counter()
    while last < end:
        now = time.perf_counter()
        if now - last > 50e-6:
            gaps.append(now - last)
        last = now
    return {
        "sleep 1 ms overshoot median [ms]": overshoot[len(overshoot) // 2],
        "sleep 1 ms overshoot p99 [ms]": overshoot[int(0.99 * (len(overshoot) - 1))],
        "preemptions over 50 us per s": len(gaps) / seconds,
        "longest preemption [ms]": max(gaps, default=0.0) * 1e3,
        "CPU taken by others [%]": 100.0 * sum(gaps) / seconds,
    }


def attribution_table(
    steps: int,
    step_ms: tuple[int, ...] = (1, 5, 10),
    conditions: tuple[Condition, ...] = ATTRIBUTION,
    machine_s: float = 2.0,
) -> Table:
    table = Table(
        key="step_precision_attribution",
        title=f"Where step misses come from: {steps} steps of each length per condition",
        columns=[
            "condition",
            *[f"{ms} ms within 5%" for ms in step_ms],
            *[f"{ms} ms within 1%" for ms in step_ms],
            *[f"{ms} ms p99 late [ms]" for ms in step_ms],
        ],
    )
    for condition in progress(conditions, "step attribution", len(conditions)):
        within5: list[float | str] = []
        within1: list[float | str] = []
        p99: list[float | str] = []
        for ms in step_ms:
            late = fixed_steps(condition, ms, steps)
            if late is None:
                within5.append("not permitted")
                within1.append("-")
                p99.append("-")
                continue
            within5.append(100.0 * sum(abs(x) <= 0.05 * ms for x in late) / len(late))
            within1.append(100.0 * sum(abs(x) <= 0.01 * ms for x in late) / len(late))
            p99.append(sorted(late)[int(0.99 * (len(late) - 1))])
        table.rows.append([condition.label, *within5, *within1, *p99])
    machine = machine_figures(machine_s)
    table.notes.append(
        "The machine alone (one thread, nothing else of ours running): "
        + "; ".join(f"{k} {v:.2f}" for k, v in machine.items())
        + "."
    )
    table.series["machine"] = machine
    return table
