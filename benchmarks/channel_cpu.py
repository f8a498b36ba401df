"""The controller's CPU per step over the network: a robot served by ``ego serve`` on TCP
and the same robot served as a Zenoh node, each in a process of its own, rounds
interleaved in one run. What it measures: ``time.process_time`` of the controller's
process per step (its channel, its devices, its step clock), not the server's."""

from __future__ import annotations

import socket
import subprocess
import sys
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from functools import partial
from typing import Any

from benchmarks.common import REPO, Table, interleaved_rounds, ratio_rows, section_main

__all__ = ["main", "run"]

STEP_MS = 16


def _free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return int(probe.getsockname()[1])


@contextmanager
def _served(*args: str) -> Iterator[None]:
    proc = subprocess.Popen(
        [sys.executable, "-m", "ego", "serve", "--port", "sim", "--camera", "none", *args],
        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, cwd=REPO,
    )  # fmt: skip
    try:
        yield
    finally:
        proc.terminate()
        proc.wait(timeout=10)


def _open(port: str, **options: Any) -> Any:
    import ego

    deadline = time.monotonic() + 15
    while True:
        try:
            return ego.Robot(port, **options)
        except ego.errors.EgoError:
            if time.monotonic() > deadline:
                raise
            time.sleep(0.2)


def _steps(robot: Any, steps: int) -> float:
    robot.proximity.enable(STEP_MS)
    robot.motors.set_speed(100, 100)
    robot.step(STEP_MS)
    start = time.process_time()
    for _ in range(steps):
        robot.step(STEP_MS)
    return (time.process_time() - start) / steps


def _steps_on(opener: Callable[[], Any], steps: int) -> float:
    with opener() as robot:
        return _steps(robot, steps)


def table(steps: int, rounds: int) -> Table:
    result = Table(
        key="channel_cpu",
        title=f"Controller CPU per step over the network ({STEP_MS} ms steps, 8 proximity "
        f"values a step, {steps} steps a round, {rounds} rounds interleaved)",
        columns=["channel", "CPU per step [us]", "x TCP"],
    )
    tcp_port, zenoh_port = _free_port(), _free_port()
    with _served("--listen", f"tcp://127.0.0.1:{tcp_port}"), _served(
        "--zenoh", "--name", "bench", "--zenoh-listen", f"tcp/127.0.0.1:{zenoh_port}"
    ):
        openers: dict[str, Callable[[], Any]] = {
            "TCP (ego serve)": lambda: _open(f"tcp://127.0.0.1:{tcp_port}"),
            "Zenoh (ego serve --zenoh)": lambda: _open(
                "zenoh://bench", zenoh_connect=[f"tcp/127.0.0.1:{zenoh_port}"]
            ),
        }
        cpu = interleaved_rounds(
            {name: partial(_steps_on, opener, steps) for name, opener in openers.items()},
            rounds,
        )
    result.rows += ratio_rows(cpu, "TCP (ego serve)")
    return result


def run(quick: bool = False) -> list[Table]:
    return [table(30 if quick else 400, 1 if quick else 4)]


main = section_main(run, __doc__)


if __name__ == "__main__":
    sys.exit(main())
