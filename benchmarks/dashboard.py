"""What watching a run costs: the dashboard's CPU and memory per step, and the step
precision with a recording on and off, measured side by side in one run.

One controller process talks over a pty to the emulator in another process (so that the
CPU counted is the controller's: its steps, and the dashboard's or recorder's threads).
It steps at 32 ms with the proximity, light, accelerometer and encoders sampled every
step and the camera (160x120, a replayed photograph) every other, in interleaved blocks
of four conditions: nothing watching; a dashboard that no page has open; a dashboard
with one page (a WebSocket client in a third process, reading everything); a recording
to MCAP. CPU is the process's CPU time per step; precision is the share of steps within
1% and 5% of 32 ms, and the mean error.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

from benchmarks.common import Table, print_and_save, ratio
from benchmarks.memory import _emulator, _raw_frames

__all__ = ["main", "run"]

STEP_MS = 32
CONDITIONS = ("nothing watching", "dashboard, no page", "dashboard, one page", "recording")


@contextlib.contextmanager
def _page(url: str) -> Iterator[None]:
    page = subprocess.Popen([sys.executable, "-m", "benchmarks._dashboard_page", url],
                            stdout=subprocess.PIPE, text=True)  # fmt: skip
    try:
        assert page.stdout is not None and page.stdout.readline().strip() == "connected"
        yield
    finally:
        page.terminate()
        page.wait()


def _block(robot: Any, steps: int) -> tuple[float, list[float]]:
    """CPU seconds of this process over ``steps`` steps, and each step's length (ms)."""
    robot.step(STEP_MS)  # anchors the clock after a change of condition
    cpu0, last = time.process_time(), time.perf_counter()
    lengths = []
    for _ in range(steps):
        robot.step(STEP_MS)
        now = time.perf_counter()
        lengths.append((now - last) * 1000.0)
        last = now
    return time.process_time() - cpu0, lengths


def measure(blocks: int, steps: int, folder: Path) -> dict[str, dict[str, Any]]:
    import ego
    from ego.camera import FileReplaySource
    from ego.core.scheduler import tune_for_stepping
    from ego.recording.writer import Recorder
    from ego.servers.dashboard.live import RobotDashboard

    tune_for_stepping()
    frames = _raw_frames(folder, 160, 120)
    results = {c: {"cpu_s": 0.0, "steps": 0, "lengths": []} for c in CONDITIONS}
    with (
        _emulator() as (_, port),
        ego.Robot(
            port, camera_source=FileReplaySource(frames, 160, 120), handle_signals=False
        ) as robot,
    ):
        for family in (robot.proximity, robot.light, robot.accelerometer, robot.encoders):
            family.enable(STEP_MS)
        robot.camera.set_size(160, 120)
        robot.camera.enable(2 * STEP_MS)
        board = RobotDashboard("127.0.0.1:0", out=open("/dev/null", "w"))  # noqa: SIM115
        board.attach(robot)
        feed, server = board.feed, board.server
        assert feed is not None and server is not None
        robot.remove_step_hooks(feed.on_step)
        robot.remove_step_hooks(feed.desk.guard)
        try:
            for block in range(blocks):
                for condition in CONDITIONS:
                    with contextlib.ExitStack() as stack:
                        if condition.startswith("dashboard"):
                            robot.add_step_guard(feed.desk.guard)
                            robot.add_step_listener(feed.on_step)
                            stack.callback(robot.remove_step_hooks, feed.on_step)
                            stack.callback(robot.remove_step_hooks, feed.desk.guard)
                            if condition.endswith("one page"):
                                stack.enter_context(_page(server.url))
                        elif condition == "recording":
                            recorder = Recorder(folder / f"block{block}.mcap")
                            recorder.attach(robot)
                            stack.callback(recorder.close)
                        cpu, lengths = _block(robot, steps)
                    results[condition]["cpu_s"] += cpu
                    results[condition]["steps"] += steps
                    results[condition]["lengths"].extend(lengths)
        finally:
            board.close()
    return results


def memory(steps: int = 100) -> dict[str, int]:
    with _emulator() as (_, port):
        out = subprocess.run([sys.executable, "-m", "benchmarks._dashboard_memory", port,
                              str(steps)],
                             capture_output=True, text=True, timeout=120, check=True)  # fmt: skip
    return dict(json.loads(out.stdout.strip().splitlines()[-1]))


def run(quick: bool = False) -> list[Table]:
    blocks, steps = (1, 10) if quick else (4, 150)
    with tempfile.TemporaryDirectory() as tmp:
        results = measure(blocks, steps, Path(tmp))
        mem = memory(5 if quick else 100)
    base = results["nothing watching"]
    base_cpu_us = base["cpu_s"] / base["steps"] * 1e6
    table = Table(
        key="dashboard_cost",
        title=f"Watching a run: CPU per step and step precision at {STEP_MS} ms "
        f"({blocks} interleaved blocks of {steps} steps per condition)",
        columns=["condition", "CPU [us/step]", "added [us/step]", "CPU ratio",
                 "within 1%", "within 5%", "mean error [ms]", "error ratio"],
    )  # fmt: skip
    base_error = statistics.fmean(abs(x - STEP_MS) for x in base["lengths"])
    for condition in CONDITIONS:
        r = results[condition]
        cpu_us = r["cpu_s"] / r["steps"] * 1e6
        errors = [abs(x - STEP_MS) / STEP_MS for x in r["lengths"]]
        mean_error = statistics.fmean(abs(x - STEP_MS) for x in r["lengths"])
        table.rows.append([
            condition, cpu_us, cpu_us - base_cpu_us, ratio(cpu_us, base_cpu_us),
            100.0 * sum(e <= 0.01 for e in errors) / len(errors),
            100.0 * sum(e <= 0.05 for e in errors) / len(errors),
            mean_error, ratio(mean_error, base_error),
        ])  # fmt: skip
    grown_mb = (mem["after_kb"] - mem["before_kb"]) / 1024
    table.notes.append(
        f"Memory: a controller's resident set grows by {grown_mb:.1f} MB when a dashboard "
        f"starts and one page connects ({mem['before_kb'] / 1024:.1f} MB "
        f"before, {mem['after_kb'] / 1024:.1f} MB after; aiohttp's import is most of it). "
        "Off, the dashboard costs nothing: no listener, no guard, nothing imported."
    )
    table.notes.append(
        "The page gets at most 25 samples and 10 JPEG frames a second; the recorder hands "
        "each step to its writer thread and encodes there."
    )
    return [table]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="a smoke run: one short block")
    args = parser.parse_args(argv)
    print_and_save(run(quick=args.quick), args.quick)
    return 0


if __name__ == "__main__":
    sys.exit(main())
