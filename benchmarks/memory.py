"""Memory: peak resident set of a controller and of the emulator, beside the Overo's 256 MB.

The thesis set out to characterise "memory utilization" but chapter 5 gives no figure; the
budget is the Gumstix Overo's 256 MB of RAM (section 2). Measured here, each in a process
of its own (peak resident set, ``VmHWM`` of ``/proc/<pid>/status``):

- a bare Python, then with ``import ego``, then with ``ego.camera`` too (numpy, OpenCV);
- a controller (``benchmarks/_memory_controller.py``): every sensor the firmware serves
  enabled at 64 ms, the camera at 640x480 saving a JPEG every step, N steps of 64 ms,
  talking over a pty to the emulator (``python -m firmware_sim``) run as another process;
  frames are replayed from a raw RGB565 file of the photograph the camera tables use
  (the emulator's rendered world lives in the other process);
- the emulator itself, read while the controller runs against it;
- the controller's peak at 160x120, 320x240 and 640x480.

Figures are from this machine (64-bit CPython and wheels); a 32-bit ARM build of the same
stack on the Overo is smaller, so the shares are an upper estimate.
"""

from __future__ import annotations

import contextlib
import json
import os
import subprocess
import sys
import tempfile
from collections.abc import Iterator
from pathlib import Path
from typing import Any

from benchmarks.common import REPO, Interrupted, Stats, Table, fmt, progress

__all__ = ["OVERO_RAM_MB", "measure_controller", "measure_snippet", "run"]

OVERO_RAM_MB = 256.0
#: What a bare interpreter is asked to import, cumulatively.
SNIPPETS = {
    "Python alone": "pass",
    "Python + import ego": "import ego",
    "Python + import ego, ego.camera (numpy, OpenCV)": "import ego, ego.camera",
}
_PEAK = (
    "\nwith open('/proc/self/status') as f:\n"
    "    print(next(int(l.split()[1]) for l in f if l.startswith('VmHWM:')))"
)
_ENV = {
    **os.environ,
    "PYTHONPATH": os.pathsep.join(p for p in (str(REPO), os.environ.get("PYTHONPATH")) if p),
}


def _mb(kb: float) -> float:
    """kB as /proc reports them (1024 bytes) to MB as RAM is counted (2^20 bytes)."""
    return kb / 1024


def measure_snippet(code: str) -> float:
    """Peak resident set (MB) of a fresh interpreter that runs ``code``."""
    out = subprocess.run(
        [sys.executable, "-c", code + _PEAK],
        check=True,
        capture_output=True,
        text=True,
        cwd=REPO,
        env=_ENV,
    ).stdout
    return _mb(int(out.split()[-1]))


def _status_kb(pid: int, field: str) -> int | None:
    try:
        with open(f"/proc/{pid}/status") as f:
            for line in f:
                if line.startswith(field + ":"):
                    return int(line.split()[1])
    except OSError:
        return None
    return None


@contextlib.contextmanager
def _emulator() -> Iterator[tuple[subprocess.Popen[str], str]]:
    """``python -m firmware_sim`` in its own process; yields it and its pty path."""
    proc = subprocess.Popen(
        [sys.executable, "-m", "firmware_sim"],
        stdout=subprocess.PIPE,
        stderr=subprocess.DEVNULL,
        text=True,
        cwd=REPO,
        env=_ENV,
    )
    try:
        assert proc.stdout is not None
        path = proc.stdout.readline().strip()
        if not path:
            raise RuntimeError("the emulator printed no pty path")
        yield proc, path
    finally:
        proc.terminate()
        try:
            proc.wait(timeout=5)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()


def _raw_frames(folder: Path, width: int, height: int) -> Path:
    """A raw RGB565 file of one frame of the photograph, as the driver delivers it."""
    from benchmarks.camera_measure import natural_frame

    path = folder / f"frame_{width}x{height}.raw"
    if not path.exists():
        path.write_bytes(natural_frame(width, height))
    return path


def measure_controller(width: int, height: int, steps: int, folder: Path) -> dict[str, Any]:
    """One controller run against a fresh emulator: the controller's report + the emulator's."""
    frames = _raw_frames(folder, width, height)
    with _emulator() as (emulator, port):
        done = subprocess.run(
            [
                sys.executable,
                "-m",
                "benchmarks._memory_controller",
                port,
                str(frames),
                str(width),
                str(height),
                str(steps),
                str(folder),
            ],
            capture_output=True,
            text=True,
            cwd=REPO,
            env=_ENV,
            timeout=60 + steps,
        )
        emulator_kb = _status_kb(emulator.pid, "VmHWM")
    lines = done.stdout.strip().splitlines()
    if done.returncode != 0 or not lines:
        raise RuntimeError(
            f"the controller failed ({done.returncode}): {done.stderr.strip()[-800:]}"
        )
    result = json.loads(lines[-1])
    result["emulator_kb"] = emulator_kb
    return result


def _cell(stats: Stats) -> str:
    return f"{fmt(stats.median, 1)} ({fmt(stats.low, 1)}-{fmt(stats.high, 1)})"


def _share(mb: float) -> float:
    return 100 * mb / OVERO_RAM_MB


@contextlib.contextmanager
def _interruptible(build: Any) -> Iterator[None]:
    try:
        yield
    except KeyboardInterrupt:
        raise Interrupted(build()) from None


def run(quick: bool = False) -> list[Table]:
    sizes = ((160, 120),) if quick else ((160, 120), (320, 240), (640, 480))
    runs, steps = (1, 20) if quick else (3, 100)
    bare: dict[str, list[float]] = {name: [] for name in SNIPPETS}
    controller: dict[tuple[int, int], list[dict[str, Any]]] = {size: [] for size in sizes}
    jobs: list[tuple[str, Any]] = [("snippet", name) for name in SNIPPETS for _ in range(runs)]
    # Runs interleaved by size, so that a slow moment does not hit one size only.
    jobs += [("controller", size) for _ in range(runs) for size in sizes]
    with tempfile.TemporaryDirectory(prefix="ego-memory-") as tmp:

        def build() -> list[Table]:
            return _tables(bare, controller, steps)

        with _interruptible(build):
            for kind, what in progress(jobs, "memory", total=len(jobs)):
                if kind == "snippet":
                    bare[what].append(measure_snippet(SNIPPETS[what]))
                else:
                    controller[what].append(measure_controller(*what, steps, Path(tmp)))
    return build()


def _tables(
    bare: dict[str, list[float]],
    controller: dict[tuple[int, int], list[dict[str, Any]]],
    steps: int,
) -> list[Table]:
    peak = Table(
        key="memory_peak",
        title=f"Peak resident memory (MB) beside the Overo's {OVERO_RAM_MB:.0f} MB of RAM",
        columns=["process", "runs", "peak MB", f"% of {OVERO_RAM_MB:.0f} MB", "what"],
    )
    for name, values in bare.items():
        if values:
            stats = Stats.of(values)
            peak.rows.append([name, stats.n, _cell(stats), _share(stats.median), "imports only"])
    done = {size: results for size, results in controller.items() if results}
    largest = max(done, key=lambda s: s[0] * s[1]) if done else None
    if largest is not None:
        results = done[largest]
        w, h = largest
        ctl = Stats.of([_mb(r["peak_kb"]) for r in results])
        emu_values = [_mb(r["emulator_kb"]) for r in results if r["emulator_kb"]]
        enabled = ", ".join(results[0]["enabled"])
        peak.rows.append(
            [
                f"controller, camera {w}x{h}",
                ctl.n,
                _cell(ctl),
                _share(ctl.median),
                f"{steps} steps of 64 ms; sensors at 64 ms; a JPEG (q90) saved every step",
            ]
        )
        if emu_values:
            emu = Stats.of(emu_values)
            peak.rows.append(
                [
                    "emulator (python -m firmware_sim)",
                    emu.n,
                    _cell(emu),
                    _share(emu.median),
                    "its own process, read during the controller's run",
                ]
            )
        peak.notes.append(
            f"Sensors enabled: {enabled}. Camera frames replayed from a raw RGB565 file "
            "(the camera tables' photograph) with ego's FileReplaySource: the emulator's "
            "rendered world lives in its own process. On the robot there is no emulator; "
            "the dsPIC answers instead."
        )
    peak.notes.append(
        "Peak resident set: VmHWM of /proc/<pid>/status, median (min-max) over the runs, "
        "MB = 2^20 bytes as RAM is counted. The thesis gives no memory figure; the Overo's "
        "256 MB is the budget. 64-bit CPython and wheels here: a 32-bit ARM build is "
        "smaller, so the shares are an upper estimate."
    )
    tables = [peak]
    if done:
        tables.append(_growth_table(done, steps))
    return tables


def _growth_table(done: dict[tuple[int, int], list[dict[str, Any]]], steps: int) -> Table:
    table = Table(
        key="memory_image_size",
        title="Controller peak memory (MB) against camera size",
        columns=[
            "size",
            "pixels",
            "runs",
            "controller peak MB",
            "after imports MB",
            "growth over imports MB",
            "raw + RGB888 frame MB",
            f"% of {OVERO_RAM_MB:.0f} MB",
            "emulator MB",
            "JPEG kB",
        ],
    )
    xs, peaks, imports, emulator = [], [], [], []
    for (w, h), results in sorted(done.items(), key=lambda item: item[0][0] * item[0][1]):
        ctl = Stats.of([_mb(r["peak_kb"]) for r in results])
        imp = Stats.of([_mb(r["after_import_kb"]) for r in results])
        emu = [_mb(r["emulator_kb"]) for r in results if r["emulator_kb"]]
        emu_median = Stats.of(emu).median if emu else float("nan")
        table.rows.append(
            [
                f"{w}x{h}",
                w * h,
                ctl.n,
                _cell(ctl),
                imp.median,
                ctl.median - imp.median,
                w * h * 5 / 2**20,
                _share(ctl.median),
                emu_median,
                results[0]["jpeg_bytes"] / 1000,
            ]
        )
        xs.append(w * h)
        peaks.append(ctl.median)
        imports.append(imp.median)
        emulator.append(emu_median)
    table.notes.append(
        f"Each run: {steps} steps of 64 ms, all sensors and the camera at 64 ms, a JPEG "
        "saved every step. 'after imports': the same process' peak once ego and ego.camera "
        "(numpy, OpenCV) are imported, before the robot opens; growth: what the robot, the "
        "link, the camera's buffers and encoding add. 'raw + RGB888 frame': 5 bytes a pixel, "
        "one frame as the driver hands it plus its converted image, for scale."
    )
    table.series.update(
        curves={
            "controller peak": (xs, peaks, {"color": "C0", "marker": "o", "linestyle": "-"}),
            "controller after imports": (
                xs,
                imports,
                {"color": "C0", "marker": ".", "linestyle": ":"},
            ),
            "emulator peak": (xs, emulator, {"color": "C1", "marker": "s", "linestyle": "-"}),
        },
        xlabel="camera pixels",
        ymin=0,
        ylabel=f"peak resident MB (the Overo has {OVERO_RAM_MB:.0f})",
    )
    return table


if __name__ == "__main__":
    for t in run(quick=True):
        t.print()
