"""``python -m benchmarks`` / ``ego bench``: reproduce the thesis' tables and write the report."""

from __future__ import annotations

import argparse
import importlib
import logging
import os
import platform
import sys
import threading
import time
from datetime import datetime, timezone

from benchmarks.common import RESULTS, Table

#: Sections in report order: module name under benchmarks/, and what it reproduces.
SECTIONS = {
    "startup": "Startup: import ego and a controller's first import",
    "serial_link": "Command overhead and serial link rate (Tables 4.1-4.2, sections 4.1.1, 5.2)",
    "step_precision": "Time-step precision (Tables 4.6-4.7)",
    "step_cost": "CPU of one avoidance step: a bare client, ego's core and the Webots face",
    "camera_tables": "Camera: acquisition, rotation, encoding (Tables 5.1-5.8) and peers",
    "memory": "Memory: peak resident set of a controller and of the emulator",
    "remote_roundtrip": "Remote control: step round trip over TCP/UDP vs the pty link",
    "epuck2_link": "The e-puck2 over USB and WiFi (with and without its camera) beside the e-puck1",
    "security": "Remote control under attack: the deadman and the client under floods",
    "webots_camera": "The Webots face's camera calls at 52x39, 160x120 and 640x480",
    "dashboard": "Watching a run: the dashboard's and the recorder's cost per step",
    "swarm": "Swarms: 2 to 16 robots over Zenoh and over UDP, side by side",
    "virtual_time": "Virtual time: the avoidance controller in real time and with --fast",
    "step_overlap": "Webots' stepBegin/stepEnd: a computing controller's step beside plain step",
    "ros2_bridge": "ROS 2: what the bridge adds to a robot's step, beside the Overo's budget",
    "pipuck_i2c": "The Pi-puck's I2C at 100 and 400 kHz beside ego's CPU and the other links",
    # Last: a Zenoh client in this process leaves the security section's TCP server
    # resetting its handshakes when it runs after it (seen, not yet understood).
    "channel_cpu": "The controller's CPU per step over TCP and over Zenoh",
}


def machine_description() -> str:
    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo") as f:
            names = [line.split(":", 1)[1].strip() for line in f if line.startswith("model name")]
        if names:
            cpu = f"{names[0]} x {len(names)}"
    except OSError:
        pass
    return f"{cpu}; Linux {platform.release()}; Python {platform.python_version()}"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m benchmarks", description=__doc__)
    parser.add_argument(
        "--quick",
        action="store_true",
        help="few repetitions and small sizes: a smoke test, asserts nothing",
    )
    parser.add_argument(
        "--only",
        action="append",
        choices=sorted(SECTIONS),
        help="run only these sections (repeatable)",
    )
    parser.add_argument(
        "--out",
        default=None,
        help="results folder (default benchmarks/results, "
        "or benchmarks/results/quick with --quick)",
    )
    args = parser.parse_args(argv)
    logging.basicConfig(level=logging.ERROR)
    out = (
        RESULTS / "quick"
        if args.quick and args.out is None
        else (RESULTS if args.out is None else __import__("pathlib").Path(args.out))
    )
    sections = args.only or list(SECTIONS)
    done: list[tuple[str, list[Table], float]] = []
    interrupted = False
    started = time.time()
    for name in sections:
        t0 = time.perf_counter()
        try:
            module = importlib.import_module(f"benchmarks.{name}")
            tables = module.run(quick=args.quick)
        except KeyboardInterrupt as exc:
            print(
                f"\ninterrupted during {name}: keeping the sections that finished", file=sys.stderr
            )
            interrupted = True
            partial: list[Table] = getattr(exc, "tables", [])  # common.Interrupted
            for table in partial:
                table.print()
                table.write_csv(out)
            if partial:
                done.append((name, partial, time.perf_counter() - t0))
            break
        for table in tables:
            table.print()
            table.write_csv(out)
        done.append((name, tables, time.perf_counter() - t0))
        # One line a section on stderr (progress bars show only on a terminal).
        print(f"section {name}: {time.perf_counter() - t0:.1f} s", file=sys.stderr, flush=True)
    from benchmarks.report import write_report

    path = write_report(
        out,
        done,
        machine_description(),
        datetime.fromtimestamp(started, timezone.utc),
        quick=args.quick,
        interrupted=interrupted,
    )
    print(f"\nreport: {path}")
    if left := _threads_left():
        # Python would wait for them at exit, for ever: say which, and end now.
        print(f"error: the benchmarks left {len(left)} thread(s) running: {', '.join(left)}",
              file=sys.stderr, flush=True)  # fmt: skip
        sys.stdout.flush()
        os._exit(1)
    return 130 if interrupted else 0


def _threads_left() -> list[str]:
    """The threads (not daemons: those Python does not wait for) still running once every
    section has closed what it opened."""
    main = threading.main_thread()
    return [t.name for t in threading.enumerate() if t is not main and not t.daemon]


if __name__ == "__main__":
    sys.exit(main())
