"""The child of benchmarks/pipuck_i2c.py: a robot on the emulated Pi-puck (the shim's
``/dev/i2c-N``, set up by the parent's environment), stepped ``argv[2]`` times with the
families of ``argv[1]`` ("avoidance" or "full") enabled; prints JSON: the bytes on the
I2C wire per step, ego's CPU per step, and the transfers per step."""

from __future__ import annotations

import json
import sys
import time

import ego

FULL = ("proximity", "light", "encoders", "microphones", "accelerometer", "gyro", "tof",
        "floor")  # fmt: skip


def main() -> None:
    which, steps = sys.argv[1], int(sys.argv[2])
    with ego.Robot("pipuck", robot="epuck2", camera_device="none") as robot:
        for name in FULL if which == "full" else ("proximity",):
            robot.family(name).enable(32)  # type: ignore[attr-defined]
        channel = robot.channel
        bus = channel.bus  # type: ignore[attr-defined]
        robot.motors.set_speed(200, -200)
        robot.step(32)  # warm-up: the chips found, the ToF started
        before, cpu0 = bus.wire_bytes, time.process_time()
        for i in range(steps):
            robot.motors.set_speed(200 + (i % 2), -200)  # a new command every step
            robot.step(32)
        cpu = (time.process_time() - cpu0) / steps
        print(json.dumps({"wire_bytes": (bus.wire_bytes - before) / steps, "cpu_s": cpu}))


if __name__ == "__main__":
    main()
