"""One robot of ``benchmarks.swarm``, in a process of its own:
``python -m benchmarks._swarm_robot PORT STEPS`` steps the robot at PORT (``zenoh://NAME``
or ``udp://HOST:PORT``) every 64 ms with its proximity sensors, and on Zenoh sends a
timestamped radio packet each step and timestamps what it receives. Prints one JSON
line: each step's length (ms), each packet's latency (ms), and the process's CPU time.
"""

from __future__ import annotations

import json
import resource
import sys
import time

STEP_MS = 64


def main(port: str, steps: int) -> int:
    import ego
    from ego.core.scheduler import tune_for_stepping

    tune_for_stepping()
    lengths: list[float] = []
    latencies: list[float] = []
    with ego.Robot(port, handle_signals=False) as robot:
        radio = None
        if port.startswith("zenoh://"):
            import zenoh

            from ego.zenoh_net.radio import Radio

            session = robot.channel.session_of(zenoh.Session)
            assert session is not None, f"{port} runs on no Zenoh session"
            radio = Radio(session, port, lambda: None)
            radio.listen(1)
        robot.proximity.enable(STEP_MS)
        robot.step(STEP_MS)
        cpu0 = resource.getrusage(resource.RUSAGE_SELF)
        last = time.perf_counter()
        for _ in range(steps):
            if radio is not None:
                radio.send(1, repr(time.time()).encode(), -1.0)
            robot.step(STEP_MS)
            now = time.perf_counter()
            lengths.append((now - last) * 1000.0)
            last = now
            if radio is not None:
                latencies += [(p.arrived_s - float(p.data)) * 1000.0 for p in radio.take()]
        cpu1 = resource.getrusage(resource.RUSAGE_SELF)
        if radio is not None:
            radio.close()
    cpu_s = (cpu1.ru_utime - cpu0.ru_utime) + (cpu1.ru_stime - cpu0.ru_stime)
    print(json.dumps({"lengths": lengths, "latencies": latencies, "cpu_s": cpu_s}), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], int(sys.argv[2])))
