"""Virtual time: the avoidance controller (8 proximity sensors, 2 motors, 32 ms steps) on
the emulator in real time and with ``--fast``, rounds interleaved in one run.

What it measures: controller steps per second of wall time, and so how much faster than
real time a learning controller can run. Each fast step still exchanges the same serial
batch with the emulator over its pty, so the link's round trip bounds the speed-up.
"""

from __future__ import annotations

import statistics
import sys
import time

from benchmarks.common import Table, section_main

__all__ = ["main", "run"]

STEP_MS = 32


def _avoid(fast: bool, sim_s: float) -> tuple[int, float]:
    """Steps taken and wall seconds for ``sim_s`` of controller time."""
    from ego.controller import Robot
    from ego.faces import default_robot, runtime

    options = runtime.RunOptions(port="sim", seed=1, fast=fast)
    with default_robot.activate(default_robot.FaceContext(options)):
        robot = Robot()
        try:
            sensors = [robot.getDevice(f"ps{i}") for i in range(8)]
            for sensor in sensors:
                sensor.enable(STEP_MS)  # type: ignore[union-attr]
            left, right = robot.getDevice("left wheel motor"), robot.getDevice("right wheel motor")
            for motor in (left, right):
                motor.setPosition(float("inf"))  # type: ignore[union-attr]
            steps, started = 0, time.perf_counter()
            while robot.step(STEP_MS) != -1 and robot.getTime() < sim_s:
                values = [s.getValue() for s in sensors]  # type: ignore[union-attr]
                turn = max(values[0], values[7]) > 100
                left.setVelocity(-3.0 if turn else 5.0)  # type: ignore[union-attr]
                right.setVelocity(3.0 if turn else 5.0)  # type: ignore[union-attr]
                steps += 1
            return steps, time.perf_counter() - started
        finally:
            robot.cleanup()


def table(sim_s: float, rounds: int) -> Table:
    result = Table(
        key="virtual_time",
        title=f"Avoidance controller, {sim_s:g} s of controller time a run, {rounds} rounds "
        "interleaved, real time vs --fast (virtual time)",
        columns=["mode", "steps/s (median)", "wall s per simulated s", "speed-up"],
    )
    rates: dict[bool, list[float]] = {False: [], True: []}
    for _ in range(rounds):
        for fast in (False, True):
            steps, wall = _avoid(fast, sim_s)
            rates[fast].append(steps / wall)
    real = statistics.median(rates[False])
    for fast, label in ((False, "real time"), (True, "--fast")):
        rate = statistics.median(rates[fast])
        result.rows.append([label, rate, (1000 / STEP_MS) / rate, rate / real])
    return result


def run(quick: bool = False) -> list[Table]:
    return [table(0.5 if quick else 5.0, 1 if quick else 3)]


main = section_main(run, __doc__)


if __name__ == "__main__":
    sys.exit(main())
