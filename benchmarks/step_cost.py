"""What one avoidance step costs the controller's process: a bare Python client, ego's core
Robot and the Webots face, each stepping the same batch on the same emulated pty.

The emulator runs in a process of its own (``python -m firmware_sim``), so the CPU time
measured (``time.process_time``) is the controller's alone: its link, its devices, its
step clock and the avoidance arithmetic (8 proximity values in, two wheel speeds out).
The bare client writes the very batch bytes ego sends (taken from ego's own batch once)
and reads the reply with os.read and select, with no step clock. Contenders alternate
round by round; medians.
"""

from __future__ import annotations

import os
import select
import sys
import time
from collections.abc import Callable

from benchmarks.common import (
    Table,
    emulator_process,
    interleaved_rounds,
    ratio_rows,
    section_main,
)

__all__ = ["main", "run"]

STEP_MS = 32


def _avoid(values: list[float]) -> tuple[float, float]:
    front = max(values[0], values[7])
    return (-300.0, 300.0) if front > 100 else (500.0, 500.0)


def _core_steps(port: str, steps: int) -> float:
    import ego

    with ego.Robot(port) as robot:
        robot.proximity.enable(STEP_MS)
        robot.step(STEP_MS)
        start = time.process_time()
        for _ in range(steps):
            left, right = _avoid(list(robot.proximity.values))
            robot.motors.set_speed(int(left), int(right))
            robot.step(STEP_MS)
        return (time.process_time() - start) / steps


def _face_steps(port: str, steps: int) -> float:
    from ego.controller import Robot
    from ego.faces import default_robot, runtime

    options = runtime.RunOptions(port=port)
    with default_robot.activate(default_robot.FaceContext(options)):
        robot = Robot()
        try:
            sensors = [robot.getDevice(f"ps{i}") for i in range(8)]
            for sensor in sensors:
                sensor.enable(STEP_MS)  # type: ignore[union-attr]
            wheels = [robot.getDevice(f"{side} wheel motor") for side in ("left", "right")]
            for wheel in wheels:
                wheel.setPosition(float("inf"))  # type: ignore[union-attr]
            robot.step(STEP_MS)
            start = time.process_time()
            for _ in range(steps):
                left, right = _avoid([s.getValue() for s in sensors])  # type: ignore[union-attr]
                wheels[0].setVelocity(left * 0.00628)  # type: ignore[union-attr]
                wheels[1].setVelocity(right * 0.00628)  # type: ignore[union-attr]
                robot.step(STEP_MS)
            return (time.process_time() - start) / steps
        finally:
            robot.cleanup()


def _batch_bytes(port: str) -> tuple[bytes, int]:
    """The bytes of ego's avoidance batch (N and D) and its reply's size."""
    import ego

    seen: list[tuple[bytes, int]] = []
    with ego.Robot(port) as robot:
        robot.tap_channel(lambda batch, reply: seen.append((batch.tx, len(reply))))
        robot.proximity.enable(STEP_MS)
        robot.step(STEP_MS)
        robot.motors.set_speed(500, 500)
        robot.step(STEP_MS)
    return seen[-1]


def _bare_steps(port: str, steps: int, tx: bytes, reply_size: int) -> float:
    """A bare client: the same bytes, os.write / select / os.read, a plain sleep."""
    import struct

    fd = os.open(port, os.O_RDWR | os.O_NOCTTY | os.O_NONBLOCK)
    try:
        start = time.process_time()
        next_step = time.perf_counter()
        for _ in range(steps):
            os.write(fd, tx)
            reply = b""
            while len(reply) < reply_size:
                select.select([fd], [], [], 0.1)
                reply += os.read(fd, reply_size - len(reply))
            values = list(struct.unpack_from("<8h", reply))
            _avoid([float(v) for v in values])
            next_step += STEP_MS / 1000
            time.sleep(max(0.0, next_step - time.perf_counter()))
        return (time.process_time() - start) / steps
    finally:
        os.close(fd)


def table(steps: int, rounds: int) -> Table:
    result = Table(
        key="step_cost",
        title=f"CPU of one avoidance step in the controller's process ({STEP_MS} ms steps, "
        f"{steps} steps a round, {rounds} rounds interleaved; emulator in its own process)",
        columns=["contender", "CPU per step [us]", "x bare client"],
    )
    with emulator_process("--firmware", "webots") as port:
        tx, reply_size = _batch_bytes(port)
        contenders: dict[str, Callable[[], float]] = {
            "bare Python client": lambda: _bare_steps(port, steps, tx, reply_size),
            "ego core Robot": lambda: _core_steps(port, steps),
            "ego Webots face": lambda: _face_steps(port, steps),
        }
        cpu = interleaved_rounds(contenders, rounds)
    result.rows += ratio_rows(cpu, "bare Python client")
    return result


def run(quick: bool = False) -> list[Table]:
    return [table(20 if quick else 300, 1 if quick else 5)]


main = section_main(run, __doc__)


if __name__ == "__main__":
    sys.exit(main())
