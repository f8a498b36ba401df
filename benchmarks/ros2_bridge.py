"""What the ROS 2 bridge adds to a robot's step: CPU per step and resident memory, as
ratios in one run, and what that is of the Overo's budget (600 MHz ARM, 256 MB).

One process holds the robot (the emulator runs in its own process on a pty, so the CPU
counted is the robot's steps and the bridge's work) with the sensors epuck_ros2
publishes enabled every step: proximity, light, floor, accelerometer, encoders.
Interleaved blocks of steps alternate the robot alone and the robot bridged
(``ego ros2``'s bridge: every sensor topic of the robot built, CDR-encoded and put on
loopback Zenoh with its attachment; a subscriber in another process takes them all, so
every put is delivered). The camera is left out: it goes out only while someone
subscribes to an image (camera_tables measures the conversions). Memory is the
process's resident set before the bridge is imported and after it ran (eclipse-zenoh
and rosbags imported, rosbags' message store built): run alone
(``python -m benchmarks.ros2_bridge``) that is the bridge's whole cost; after another
section that imported Zenoh it is less.
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import time
from typing import Any

from benchmarks.common import Table, print_and_save, ratio
from benchmarks.memory import OVERO_RAM_MB, _emulator

__all__ = ["main", "run"]

CONDITIONS = ("robot alone", "robot bridged to ROS 2")
#: How much slower the Overo's 600 MHz Cortex-A8 runs this Python than the machine the
#: benchmark runs on: an assumption (not measured here) for the budget line only.
OVERO_SLOWDOWN = 25
_SUBSCRIBER = """
import sys, zenoh
config = zenoh.Config()
config.insert_json5("mode", '"peer"')
config.insert_json5("scouting/multicast/enabled", "false")
config.insert_json5("listen/endpoints", '["tcp/127.0.0.1:0"]')
config.insert_json5("connect/endpoints", '["%s"]')
session = zenoh.open(config)
count = [0]
sub = session.declare_subscriber("0/**", lambda sample: count.__setitem__(0, count[0] + 1))
print("ready", flush=True)
sys.stdin.readline()
sub.undeclare()
print(count[0], flush=True)
session.close()
"""


def _rss_kb() -> int:
    with open("/proc/self/status") as f:
        return next(int(line.split()[1]) for line in f if line.startswith("VmRSS:"))


def _block(robot: Any, steps: int, step_ms: int) -> float:
    robot.step(step_ms)  # anchors the clock after a change of condition
    cpu0 = time.process_time()
    for _ in range(steps):
        robot.step(step_ms)
    return time.process_time() - cpu0


def measure(blocks: int, steps: int, step_ms: int) -> dict[str, Any]:
    import ego
    from ego.core.scheduler import tune_for_stepping

    tune_for_stepping()
    endpoint = f"tcp/127.0.0.1:{_free_port()}"
    pipe = subprocess.PIPE
    subscriber = subprocess.Popen([sys.executable, "-c", _SUBSCRIBER % endpoint],
                                  stdin=pipe, stdout=pipe, text=True)  # fmt: skip
    cpu = dict.fromkeys(CONDITIONS, 0.0)
    try:
        with _emulator() as (_, port), ego.Robot(port, handle_signals=False) as robot:
            for family in (robot.proximity, robot.light, robot.floor, robot.accelerometer,
                           robot.encoders):  # fmt: skip
                family.enable(step_ms)
            cpu[CONDITIONS[0]] += _block(robot, steps, step_ms)
            rss_before = _rss_kb()
            bridge, close = _bridge(robot, endpoint, step_ms)
            assert subscriber.stdout is not None and subscriber.stdout.readline() == "ready\n"
            try:
                _block(robot, steps, step_ms)  # warm-up: the first messages, their types
                for block in range(blocks):
                    for condition in CONDITIONS if block else CONDITIONS[1:]:
                        (bridge.hook if condition != CONDITIONS[0] else bridge.detach)()
                        cpu[condition] += _block(robot, steps, step_ms)
                rss_after = _rss_kb()
                topics = len(bridge.published)
            finally:
                close()
    finally:
        try:
            out, _ = subscriber.communicate("\n", timeout=10)
        except subprocess.TimeoutExpired:
            subscriber.kill()
            raise
    return {"cpu": cpu, "steps": blocks * steps, "rss_before_kb": rss_before,
            "rss_after_kb": rss_after, "topics": topics,
            "delivered": int(out.split()[-1])}  # fmt: skip


def _bridge(robot: Any, endpoint: str, step_ms: int) -> tuple[Any, Any]:
    from ego.ros2.participant import Participant
    from ego.servers.ros2_node.bridge import Ros2Bridge
    from ego.zenoh_net.sessions import ZenohSettings, open_session

    session: Any = open_session(ZenohSettings(listen=[endpoint]))
    node = Participant(session, "epuck_driver")
    bridge = Ros2Bridge(robot, node, period_ms=step_ms).attach()

    def close() -> None:
        bridge.close()  # unhooks the steps and joins the deadman's thread
        node.close()
        session.close()

    return bridge, close


def _free_port() -> int:
    import socket

    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return int(probe.getsockname()[1])


def run(quick: bool = False) -> list[Table]:
    blocks, steps, step_ms = (2, 15, 16) if quick else (6, 150, 64)
    found = measure(blocks, steps, step_ms)
    per_step = {c: found["cpu"][c] / found["steps"] * 1e6 for c in CONDITIONS}
    base = per_step[CONDITIONS[0]]
    added_us = per_step[CONDITIONS[1]] - base
    grown_mb = (found["rss_after_kb"] - found["rss_before_kb"]) / 1024
    table = Table(
        key="ros2_bridge_cost",
        title=f"The ROS 2 bridge on the step loop: CPU per step and memory "
        f"({blocks} interleaved blocks of {steps} steps at {step_ms} ms)",
        columns=["condition", "CPU [us/step]", "added [us/step]", "CPU ratio",
                 "of a 64 ms step here", f"of 64 ms on the Overo (x{OVERO_SLOWDOWN})"],
    )  # fmt: skip
    for condition in CONDITIONS:
        us = per_step[condition]
        table.rows.append([condition, us, us - base, ratio(us, base),
                           f"{100 * us / 64e3:.2f} %",
                           f"{100 * us * OVERO_SLOWDOWN / 64e3:.1f} %"])  # fmt: skip
    table.notes.append(
        f"Memory: the resident set grows by {grown_mb:.1f} MB with the bridge "
        f"({found['rss_before_kb'] / 1024:.1f} MB before, {found['rss_after_kb'] / 1024:.1f} "
        f"MB after: {100 * grown_mb / OVERO_RAM_MB:.1f} % of the Overo's "
        f"{OVERO_RAM_MB:.0f} MB, ratio {ratio(found['rss_after_kb'], found['rss_before_kb']):.2f})."
    )
    table.notes.append(
        f"{found['topics']} topics declared, the camera's sent only while subscribed "
        f"({found['delivered']} samples reached the subscriber). The Overo column "
        f"assumes this Python runs {OVERO_SLOWDOWN} times "
        f"slower on its 600 MHz Cortex-A8 than here: an estimate, not a measurement. The "
        f"bridge adds {added_us:.0f} us a step here."
    )
    return [table]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="a smoke run: two short blocks")
    args = parser.parse_args(argv)
    print_and_save(run(quick=args.quick), args.quick)
    return 0


if __name__ == "__main__":
    sys.exit(main())
