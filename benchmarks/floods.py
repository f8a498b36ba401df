"""Floods an attacker on the network can send at ``ego serve``, each from its own process.

Used by the security benchmark and the attack tests alike. A flood runs as a child
Python process, so that its sockets count against its own file descriptors and its CPU
is its own, as an attacker's would be.
"""

from __future__ import annotations

import subprocess
import sys

__all__ = ["FLOOD_KINDS", "start_flood"]

_FLOODER = r"""
import socket, sys, time
kind, host = sys.argv[1], sys.argv[2]
port, count, seconds = int(sys.argv[3]), int(sys.argv[4]), float(sys.argv[5])
extra = bytes.fromhex(sys.argv[6]) if len(sys.argv) > 6 else b""
socks = []
end = time.monotonic() + seconds
if kind == "idle":  # sockets that connect and say nothing (slowloris, fd exhaustion)
    while time.monotonic() < end:
        for _ in range(count):
            try:
                socks.append(socket.create_connection((host, port), timeout=1))
            except OSError:
                pass
        time.sleep(0.05)
        for s in socks[:-count]:
            s.close()
        socks = socks[-count:]
elif kind == "partial":  # frames that announce a big payload and never finish it
    while time.monotonic() < end:
        try:
            s = socket.create_connection((host, port), timeout=1)
            s.sendall(extra + bytes(4096))
            socks.append(s)
        except OSError:
            pass
        socks = socks[-count:]
elif kind == "hello":  # UDP handshakes from many source ports
    socks = [socket.socket(socket.AF_INET, socket.SOCK_DGRAM) for _ in range(count)]
    while time.monotonic() < end:
        for s in socks:
            s.sendto(extra, (host, port))
        time.sleep(0.001)
"""

#: What each flood does, for tables.
FLOOD_KINDS = {
    "idle": "TCP sockets that connect and stay silent",
    "partial": "TCP frames announcing 1 MiB, never finished",
    "hello": "UDP HELLOs from 32 source ports",
}


def start_flood(
    kind: str, url: str, count: int, seconds: float, extra: bytes = b""
) -> subprocess.Popen[bytes]:
    """Start a flood of ``kind`` at ``url`` (``tcp://`` or ``udp://``) for ``seconds``."""
    if kind not in FLOOD_KINDS:
        raise ValueError(f"flood {kind!r} is not one of {', '.join(FLOOD_KINDS)}")
    host, port = url.split("://", 1)[1].rsplit(":", 1)
    args = [sys.executable, "-c", _FLOODER, kind, host, port, str(count), str(seconds)]
    return subprocess.Popen([*args, extra.hex()] if extra else args)
