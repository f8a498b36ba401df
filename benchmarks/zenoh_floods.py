"""Floods a peer on a Zenoh network can send at a robot node or a radio, each from its own
process (its own interpreter, as an attacker's would be).

Used by the Zenoh security benchmark (benchmarks/zenoh_security.py) and the Zenoh tests
alike. Each flooder is a peer session on loopback that connects to ``endpoint``.
"""

from __future__ import annotations

import subprocess
import sys
from typing import IO, cast

from benchmarks.common import flood_result

__all__ = ["flood_result", "start_ascii_flood", "start_radio_flood"]

_SESSION = r"""
import json, sys, threading, time
import zenoh
def session(endpoint, listen):
    config = zenoh.Config()
    config.insert_json5("mode", '"peer"')
    config.insert_json5("scouting/multicast/enabled", "false")
    config.insert_json5("listen/endpoints", json.dumps([listen]))
    if endpoint:
        config.insert_json5("connect/endpoints", json.dumps([endpoint]))
    return zenoh.open(config)
"""

_ASCII = _SESSION + r"""
endpoint, node, payload, who = sys.argv[1], sys.argv[2], sys.argv[3].encode(), sys.argv[4]
seconds, threads, rate = float(sys.argv[5]), int(sys.argv[6]), float(sys.argv[7])
s = session(endpoint, "tcp/127.0.0.1:0")
while not any(r.ok is not None for r in s.get(f"ego/{node}/info", timeout=1)):
    time.sleep(0.05)
print("ready", flush=True)
end = time.monotonic() + seconds
counts = {"ok": 0, "err": 0, "none": 0}
lock = threading.Lock()
def flood():
    gap = threads / rate if rate > 0 else 0.0  # each thread's share of the rate
    due = time.monotonic()
    while time.monotonic() < end:
        due += gap
        if due > time.monotonic():
            time.sleep(due - time.monotonic())
        got = "none"
        for reply in s.get(f"ego/{node}/ascii", payload=payload, attachment=who.encode(),
                           timeout=2):
            got = "ok" if reply.ok is not None else "err"
        with lock:
            counts[got] += 1
workers = [threading.Thread(target=flood) for _ in range(threads)]
for w in workers: w.start()
for w in workers: w.join()
print(json.dumps(counts), flush=True)
s.close()
"""

_RADIO = _SESSION + r"""
listen, channel, size, seconds = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), float(sys.argv[4])
meta = json.dumps({"from": "flooder", "range": -1.0, "pose": None}).encode()
s = session("", listen)
print("ready", flush=True)
end = time.monotonic() + seconds
data, sent = bytes(size), 0
while time.monotonic() < end:
    for _ in range(100):
        s.put(f"ego/radio/{channel}", data, attachment=meta)
    sent += 100
print(json.dumps({"sent": sent}), flush=True)
s.close()
"""


def _start(script: str, *args: object) -> subprocess.Popen[str]:
    process = subprocess.Popen([sys.executable, "-c", script, *map(str, args)],
                               stdout=subprocess.PIPE, text=True)  # fmt: skip
    line = cast(IO[str], process.stdout).readline().strip()
    if line != "ready":
        process.kill()
        process.wait()
        raise RuntimeError(f"the flooder did not start (it said {line!r})")
    return process


def start_ascii_flood(
    endpoint: str, node: str, *, payload: str = "V,1000", who: str = "flooder",
    seconds: float = 5.0, threads: int = 16, rate: float = 0.0,
) -> subprocess.Popen[str]:  # fmt: skip
    """A peer that, once node ``node`` answers, sends ASCII queries ``payload`` with the
    id ``who`` from ``threads`` threads for ``seconds``, then prints its replies' count;
    as fast as the replies come, or at most ``rate`` queries a second in all."""
    return _start(_ASCII, endpoint, node, payload, who, seconds, threads, rate)


def start_radio_flood(
    listen: str, *, channel: int = 1, size: int = 512, seconds: float = 5.0
) -> subprocess.Popen[str]:
    """A peer listening on ``listen`` that puts packets of ``size`` bytes on the radio's
    ``channel`` as fast as it can for ``seconds``, then prints how many it sent."""
    return _start(_RADIO, listen, channel, size, seconds)
