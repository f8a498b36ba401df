"""Floods a ROS 2 peer can send at a bridged robot's subscriptions, each from its own process
(its own interpreter, as an attacker's would be), and what the bridge does under them.

A flooder is a Zenoh peer on loopback that connects to the router ``endpoint`` (where
rmw_zenohd stands) and puts samples on one rmw_zenoh data key, each with a well-formed
33-byte attachment (rmw_zenoh drops samples without one before any decoding): a payload
that is not the topic's CDR (``malformed``) or a valid ``geometry_msgs/Twist``
(``twist``), at most ``rate`` samples a second (bounded, so that a test's flood loads a
2-core machine without taking all of it). When done it prints how many it sent and the
``time.monotonic()`` of its last put (CLOCK_MONOTONIC: one clock for every process).

Used by the ROS 2 flood tests (tests/ros2_node/test_floods.py) and by
``python -m benchmarks.ros2_floods``, which measures every attack of issue 32 (item 1)
on the code it runs on: the deadman's delay after the last command, how late the steps
came, and how many log lines the flood wrote.
"""

from __future__ import annotations

import subprocess
import sys
from typing import IO, cast

from benchmarks.common import flood_result

__all__ = ["flood_result", "start_floods", "twist_payload"]

_FLOOD = r"""
import json, struct, sys, time
import zenoh
from zenoh.ext import Int64, z_serialize
endpoint, key, kind = sys.argv[1], sys.argv[2], sys.argv[3]
rate, seconds, speed = int(sys.argv[4]), float(sys.argv[5]), float(sys.argv[6])
config = zenoh.Config()
config.insert_json5("mode", '"peer"')
config.insert_json5("scouting/multicast/enabled", "false")
config.insert_json5("listen/endpoints", json.dumps(["tcp/127.0.0.1:0"]))
config.insert_json5("connect/endpoints", json.dumps([endpoint]))
s = zenoh.open(config)
pub = s.declare_publisher(key)
end_wait = time.monotonic() + 20
while not pub.matching_status.matching and time.monotonic() < end_wait:
    time.sleep(0.02)
if kind == "twist":
    payload = b"\x00\x01\x00\x00" + struct.pack("<6d", speed, 0, 0, 0, 0, 0)
else:  # the CDR header, then 3 bytes where a Twist has 48
    payload = b"\x00\x01\x00\x00\xff\xff\xff"
gid = bytes(range(16))
print("ready", flush=True)
sys.stdin.readline()  # "go": every flooder starts at once
start = time.monotonic()
end = start + seconds
sent, seq, last = 0, 0, start
chunk = max(1, rate // 100)
while time.monotonic() < end:
    for _ in range(chunk):
        seq += 1
        pub.put(payload, attachment=z_serialize((Int64(seq), Int64(time.time_ns()), gid)))
    last = time.monotonic()
    sent += chunk
    ahead = start + sent / rate - time.monotonic()
    if ahead > 0:
        time.sleep(ahead)
print(json.dumps({"sent": sent, "last_at": last}), flush=True)
s.close()
"""


def twist_payload(linear_x: float, angular_z: float = 0.0) -> bytes:
    """A geometry_msgs/Twist in little-endian CDR (header 00 01 00 00, six float64)."""
    import struct

    return b"\x00\x01\x00\x00" + struct.pack("<6d", linear_x, 0, 0, 0, 0, angular_z)


def start_floods(count: int, endpoint: str, key: str, *, kind: str = "malformed",
                 rate: int = 2000, seconds: float = 5.0,
                 speed: float = 0.0) -> list[subprocess.Popen[str]]:  # fmt: skip
    """``count`` peers, started together, that once a subscriber on ``key`` matches put
    ``kind`` samples (``malformed``, or ``twist`` at ``speed`` m/s) at ``rate`` a second
    each for ``seconds``; returned when every one is ready."""
    args = [endpoint, key, kind, str(rate), str(seconds), str(speed)]
    processes = [subprocess.Popen([sys.executable, "-c", _FLOOD, *args], stdin=subprocess.PIPE,
                                  stdout=subprocess.PIPE, text=True)
                 for _ in range(count)]  # fmt: skip
    said = [cast(IO[str], p.stdout).readline().strip() for p in processes]
    if any(line != "ready" for line in said):
        for process in processes:
            process.kill()
            process.wait()
        raise RuntimeError(f"the flooders did not start (they said {said!r})")
    for process in processes:
        cast(IO[str], process.stdin).write("go\n")
        cast(IO[str], process.stdin).flush()
    return processes
