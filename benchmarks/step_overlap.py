"""Webots' stepBegin/stepEnd: a controller computing while its step crosses the link.

A controller that computes ``work`` ms a step (here a learning controller's kind of
work: small matrix products, which hold the GIL between them) reads the 8 proximity
and 8 light sensors and sets both wheels every step, against the emulator in a process
of its own behind a pty paced at 115200 or 230400 baud.

What it measures, per step of the controller's loop, wall time: ``wire`` is a plain
``step()`` with no work (the emulator's modelled wire time, 10 bits a byte at the baud,
plus the dsPIC's modelled work and ego's own cost: encoding, the pty, decoding);
``plain`` is ``step()`` then the work (wire + work); ``overlapped`` is ``stepBegin()``,
the work, ``stepEnd()``: it should approach max(wire, work). The controller asks for 1 ms
steps, so that no pacing wait hides either. Rounds of the three are interleaved.
"""

from __future__ import annotations

import os
import statistics
import sys
import time
import warnings
from collections.abc import Callable

import numpy as np

from benchmarks.common import Table, section_main
from benchmarks.serial_link import emulator_process

__all__ = ["main", "run"]

BAUDS = (115200, 230400)
WORK_MS = (5.0, 20.0)
#: The step asked (ms): shorter than any wire time here, so that steps overrun and
#: no pacing wait is measured.
STEP_MS = 1


def _work(ms: float) -> Callable[[], None]:
    """``ms`` of a controller's compute: 64x64 matrix products until the time is up."""
    weights = np.random.default_rng(1).standard_normal((64, 64))
    state = np.ones(64)

    def work() -> None:
        nonlocal state
        end = time.perf_counter() + ms / 1000.0
        while time.perf_counter() < end:
            state = np.tanh(weights @ state)

    return work


def _loop_ms(path: str, mode: str, work_ms: float, steps: int) -> float:
    """Median wall ms of one controller loop iteration in ``mode``."""
    from ego.controller import Robot
    from ego.faces import default_robot, runtime

    work = _work(work_ms)
    options = runtime.RunOptions(port=path)
    with default_robot.activate(default_robot.FaceContext(options)):
        robot = Robot()
        try:
            sensors = [robot.getDevice(f"{k}{i}") for k in ("ps", "ls") for i in range(8)]
            for sensor in sensors:
                sensor.enable(STEP_MS)  # type: ignore[union-attr]
            wheels = [robot.getDevice(f"{s} wheel motor") for s in ("left", "right")]
            for wheel in wheels:
                wheel.setPosition(float("inf"))  # type: ignore[union-attr]
            times = []
            for i in range(steps + 3):  # 3 to warm up
                t0 = time.perf_counter()
                speed = 1.0 + (i % 3)
                for wheel in wheels:
                    wheel.setVelocity(speed)  # type: ignore[union-attr]
                if mode == "overlapped":
                    robot.stepBegin(STEP_MS)
                    work()
                    robot.stepEnd()
                else:
                    robot.step(STEP_MS)
                    if mode == "plain":
                        work()
                _ = [s.getValue() for s in sensors]  # type: ignore[union-attr]
                times.append(time.perf_counter() - t0)
            return statistics.median(times[3:]) * 1000.0
        finally:
            robot.cleanup()


def table(steps: int, rounds: int) -> Table:
    result = Table(
        key="step_overlap",
        title=f"stepBegin/stepEnd vs step, {steps} steps a run, {rounds} rounds interleaved: "
        "ms per controller loop (wire: the emulator's modelled wire time + ego's cost)",
        columns=[
            "baud",
            "work ms",
            "wire ms",
            "plain ms",
            "overlapped ms",
            "max(wire, work)",
            "wire + work",
            "plain / overlapped",
        ],
    )
    load_before = os.getloadavg()[0]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the 1 ms steps overrun on purpose
        for baud in BAUDS:
            with emulator_process("--baud", str(baud)) as path:
                for work_ms in WORK_MS:
                    runs: dict[str, list[float]] = {"wire": [], "plain": [], "overlapped": []}
                    for _ in range(rounds):
                        for mode in runs:
                            runs[mode].append(_loop_ms(path, mode, work_ms, steps))
                    wire, plain, overlapped = (statistics.median(runs[m]) for m in runs)
                    result.rows.append([
                        str(baud), work_ms, wire, plain, overlapped, max(wire, work_ms),
                        wire + work_ms, plain / overlapped,
                    ])  # fmt: skip
    result.notes.append(
        "The emulator runs in its own process, pacing each byte at 10 bits of the baud "
        "and modelling the dsPIC's work; ego's cost (encoding, the pty, decoding, the step "
        "thread) is inside 'wire'. The work is numpy matrix products, which hold the GIL "
        "between them, as a learning controller's forward pass does. While a step is in "
        "flight the step thread needs the CPU and the GIL: on a machine busy with other "
        "work (load average here: "
        f"{load_before:.1f} before, {os.getloadavg()[0]:.1f} after, on {os.cpu_count()} "
        "CPUs), 'plain' runs beyond wire + work and the overlap gains less."
    )
    return result


def run(quick: bool = False) -> list[Table]:
    return [table(10 if quick else 60, 1 if quick else 3)]


main = section_main(run, __doc__)


if __name__ == "__main__":
    sys.exit(main())
