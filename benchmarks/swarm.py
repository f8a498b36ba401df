"""Swarms on this 2-core machine: 2, 4, 8 and 16 emulated robots at 64 ms, each driven by
a controller in a process of its own, over Zenoh (ego swarm's path) and over today's UDP
path (one ``ego serve`` server a robot), side by side in one run.

Per robot: step precision (the share of steps within 1% and 5% of 64 ms), CPU per step of
its controller process, and of the host process (emulators and servers, or Zenoh nodes)
divided by the robots; over Zenoh also the robot-to-robot latency of a radio packet
(Emitter to Receiver: put by one controller, delivered by Zenoh to every other). The UDP
path has no robot-to-robot messages at all.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import os
import statistics
import subprocess
import sys
import time
from collections.abc import Iterator
from typing import Any

from benchmarks.common import Table, print_and_save, ratio

__all__ = ["main", "run"]

STEP_MS = 64


def _free_endpoint() -> str:
    import socket

    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return f"tcp/127.0.0.1:{probe.getsockname()[1]}"


@contextlib.contextmanager
def _zenoh_robots(count: int) -> Iterator[tuple[list[str], dict[str, str]]]:
    from ego.app.swarm import Swarm, robot_name

    with Swarm(count, endpoint=_free_endpoint()) as swarm:
        yield [f"zenoh://{robot_name(i)}" for i in range(count)], swarm.controller_env()


@contextlib.contextmanager
def _udp_robots(count: int) -> Iterator[tuple[list[str], dict[str, str]]]:
    from ego.app.swarm import robot_seed
    from ego.core.registry import find_backend, open_port
    from ego.seam.profile import Firmware
    from ego.servers.socket.server import Server
    from ego.servers.socket.server_thread import ServerThread

    backend: Any = find_backend("sim")
    with contextlib.ExitStack() as stack:
        urls = []
        for world in backend.swarm_worlds(None, [robot_seed(1, i) for i in range(count)]):
            opened = open_port("sim", firmware=Firmware.WEBOTS, world=world)
            stack.callback(opened.close)
            thread = stack.enter_context(
                ServerThread(Server(opened.channel, listen=["udp://127.0.0.1:0"]))
            )
            urls.append(thread.url)
        yield urls, dict(os.environ)


def _run(path: str, count: int, steps: int) -> dict[str, Any]:
    robots = _zenoh_robots if path == "zenoh" else _udp_robots
    with robots(count) as (ports, env):
        cpu0 = time.process_time()
        processes = [
            subprocess.Popen(
                [sys.executable, "-m", "benchmarks._swarm_robot", port, str(steps)],
                stdout=subprocess.PIPE,
                text=True,
                env=env,
            )
            for port in ports
        ]
        outputs = [p.communicate(timeout=120 + steps)[0] for p in processes]
        host_cpu_s = time.process_time() - cpu0
    results = [json.loads(out.strip().splitlines()[-1]) for out in outputs]
    lengths = [x for r in results for x in r["lengths"]]
    latencies = sorted(x for r in results for x in r["latencies"])
    errors = [abs(x - STEP_MS) / STEP_MS for x in lengths]
    return {
        "within1": 100.0 * sum(e <= 0.01 for e in errors) / len(errors),
        "within5": 100.0 * sum(e <= 0.05 for e in errors) / len(errors),
        "error_ms": statistics.median(abs(x - STEP_MS) for x in lengths),
        "latency_median": statistics.median(latencies) if latencies else None,
        "latency_p99": latencies[int(0.99 * (len(latencies) - 1))] if latencies else None,
        "controller_us": statistics.fmean(r["cpu_s"] for r in results) / steps * 1e6,
        "host_us": host_cpu_s / count / steps * 1e6,
    }


def run(quick: bool = False) -> list[Table]:
    sizes, steps = ((2,), 10) if quick else ((2, 4, 8, 16), 100)
    table = Table(
        key="swarm_scaling",
        title=f"Swarms at {STEP_MS} ms on this machine: Zenoh (ego swarm) vs today's UDP path, "
        f"{steps} steps a robot, paths interleaved per size",
        columns=["robots", "path", "within 1%", "within 5%", "median error [ms]",
                 "latency median [ms]", "latency p99 [ms]", "controller CPU [us/step]",
                 "host CPU per robot [us/step]", "CPU ratio zenoh/udp"],
    )  # fmt: skip
    for count in sizes:
        measured = {path: _run(path, count, steps) for path in ("zenoh", "udp")}
        cpu = {p: m["controller_us"] + m["host_us"] for p, m in measured.items()}
        for path, m in measured.items():
            table.rows.append([
                count, path, m["within1"], m["within5"], m["error_ms"],
                "-" if m["latency_median"] is None else m["latency_median"],
                "-" if m["latency_p99"] is None else m["latency_p99"],
                m["controller_us"], m["host_us"],
                ratio(cpu["zenoh"], cpu["udp"]) if path == "zenoh" else "-",
            ])  # fmt: skip
    memory = json.loads(subprocess.run(
        [sys.executable, "-m", "benchmarks._zenoh_memory"], capture_output=True, text=True,
        timeout=120, check=True).stdout.strip().splitlines()[-1])  # fmt: skip
    table.notes.append(
        f"Memory a Zenoh peer adds to a controller (x86-64): "
        f"{(memory['imported_kb'] - memory['before_kb']) / 1024:.1f} MB to import zenoh, "
        f"{(memory['peer_kb'] - memory['before_kb']) / 1024:.1f} MB with a peer session "
        f"and the radio listening ({memory['before_kb'] / 1024:.1f} MB before)."
    )
    table.notes.append(
        "Latency: a radio packet from one robot's controller process to every other's, "
        "put before a step and timestamped on arrival (same clock). The UDP path carries "
        "batches only: it has no robot-to-robot messages to time."
    )
    return [table]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="2 robots, 10 steps")
    args = parser.parse_args(argv)
    print_and_save(run(quick=args.quick), args.quick)
    return 0


if __name__ == "__main__":
    sys.exit(main())
