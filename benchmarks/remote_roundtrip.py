"""Remote control: a full sensor step over TCP and UDP against the same step on the pty link.

Round trip: one step's batch ``a E M N O Q u`` (8 bytes out, 58 back), timed on three
links interleaved step by step (pty, TCP, UDP, pty, TCP, UDP...): the direct pty link to
an emulator in this process, and ``ego serve --port sim`` in two child processes (one
client controls a server at a time), reached over loopback TCP and UDP. The remote
step is the direct step plus the network hop and the server's own work, so the ratio
says what driving a robot from a PC costs on top of the serial line, which dominates.

CPU overhead: what ego's remote protocol costs the processor for one full step without
any I/O, timed with ``time.process_time`` over many iterations: the client encodes the
batch and frames it, the server unframes it, checks it (``parse_batch``) and frames the
reply, the client unframes the reply and decodes the values.
"""

from __future__ import annotations

import argparse
import os
import re
import subprocess
import sys
import tempfile
import time
from typing import Any

from benchmarks.common import REPO, THESIS_LINE_BAUD, Table, interleaved
from ego.backends.remote.channel import RemoteChannel
from ego.net.frames import MessageType, decode_frame, encode_frame
from ego.net.sequence import SequenceGuard
from ego.nursery import Nursery
from ego.seam.batch import Request
from ego.seam.channel import Channel
from ego.seam.profile import Command, Firmware
from ego.serial.link import Link
from ego.serial.profiles import PROFILES, wire_time_s
from ego.serial.protocol import encode_batch, parse_batch
from ego.serial.transport import SerialTransport
from firmware_sim import Emulator

__all__ = ["main", "run"]

#: The thesis' full sensor batch.
SENSORS = [
    Request(Command(c))
    for c in (
        Command.ACCELEROMETER_RAW,
        Command.GET_SPEED,
        Command.FLOOR,
        Command.PROXIMITY,
        Command.LIGHT,
        Command.GET_STEPS,
        Command.MIC_AMPLITUDE,
    )
]
#: What ``ego serve --port sim`` runs, with the emulator's line at the thesis' 230400 baud
#: (the pty link beside it runs at that rate too) and an optional shared secret.
_SERVE = (
    "import asyncio, sys\n"
    "from ego.backends import open_port\n"
    "from ego.app.serve import _serve\n"
    "from ego.servers.socket.server import Server\n"
    "opened = open_port('sim', baudrate=int(sys.argv[1]))\n"
    "server = Server(opened.channel, listen=sys.argv[2], secret=sys.argv[3] or None)\n"
    "asyncio.run(_serve(server))\n"
    "opened.close()\n"
)
#: The shared secret of the sealed server.
SECRET = "bench-secret-bench-secret"


class _ServeProcess:
    """``ego serve`` on the emulator in a child process, on one loopback URL."""

    def __init__(self, scheme: str, secret: str = "") -> None:
        self.secret = secret or None
        self._folder = tempfile.mkdtemp(prefix="ego-bench-") if scheme == "unix" else ""
        listen = (
            f"unix://{self._folder}/robot.sock" if scheme == "unix" else f"{scheme}://127.0.0.1:0"
        )
        self.process = subprocess.Popen(
            [
                sys.executable,
                "-c",
                _SERVE,
                str(THESIS_LINE_BAUD),
                listen,
                secret,
            ],
            cwd=REPO,
            stderr=subprocess.PIPE,
            text=True,
            env={**os.environ, "EGO_CAMERA": "none"},
        )
        self.url = ""
        #: The thread that keeps its log flowing once it serves.
        self.threads = Nursery("a benchmark's ego serve log")

    def wait_ready(self) -> _ServeProcess:
        """Read its log until it says where it listens (all start at once, then this)."""
        assert self.process.stderr is not None
        for line in self.process.stderr:
            match = re.search(r"ego serve: .* on (\S+)$", line)
            if match:
                self.url = match.group(1)
                break
        if not self.url:
            raise RuntimeError(f"ego serve exited with {self.process.wait()} before serving")
        # Keep its log flowing so that the pipe never fills and stalls it.
        self.threads.start_thread(self.process.stderr.read, name="bench-serve-log")
        return self

    def stop(self) -> None:
        self.process.terminate()
        try:
            self.process.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.process.kill()
            self.process.wait()
        self.threads.close()  # its log ended with it


def roundtrip_table(steps: int) -> Table:
    profile = PROFILES[Firmware.WEBOTS]
    batch = encode_batch(SENSORS, profile)
    servers = [_ServeProcess("tcp"), _ServeProcess("udp"), _ServeProcess("tcp", SECRET),
               _ServeProcess("udp", SECRET), _ServeProcess("unix")]  # fmt: skip
    emu = Emulator("webots", baud=THESIS_LINE_BAUD, seed=1).start()
    links: dict[str, Channel] = {}
    try:
        for server in servers:
            server.wait_ready()
        links["pty (direct)"] = Link(SerialTransport(emu.path), Firmware.WEBOTS)
        for server in servers:
            name = server.url.split(":")[0].upper() + (" sealed" if server.secret else "")
            name = "Unix (ego run --supervised)" if name == "UNIX" else name
            links[name] = RemoteChannel.from_url(server.url, server.secret)
        stats = interleaved(
            {name: (lambda link=link: link.exchange(batch)) for name, link in links.items()},
            repeats=steps,
        )
    finally:
        for link in links.values():
            link.close()
        emu.stop()
        for server in servers:
            server.stop()
    direct = stats["pty (direct)"].median
    wire_ms = wire_time_s(len(batch.tx) + batch.reply_size) * 1e3
    table = Table(
        key="remote_roundtrip",
        title=(
            f"Remote step round trip, full sensor batch a E M N O Q u "
            f"({len(batch.tx)} + {batch.reply_size} bytes), {steps} steps each, interleaved"
        ),
        columns=["link", "median [ms]", "min", "max", "ratio to pty", "added [ms]", "n"],
    )
    for name, s in stats.items():
        table.rows.append(
            [
                name,
                s.median * 1e3,
                s.low * 1e3,
                s.high * 1e3,
                s.median / direct,
                (s.median - direct) * 1e3,
                str(s.n),
            ]
        )
    table.notes.append(
        f"Wire time of the batch at 230400 baud: {wire_ms:.2f} ms. Loopback network; the "
        "servers run ego serve on the emulator (230400 baud) in child processes, the pty "
        "emulator in this one; sealed: with a shared secret, every frame HMAC-SHA256."
    )
    return table


def _old_step(batch_reply: bytes, guard: SequenceGuard, seq: int) -> None:
    """The step as the byte-relaying design did it: the batch's bytes framed with a CRC,
    re-parsed on the server (parse_batch) and re-encoded; kept to compare in one run."""
    profile = PROFILES[Firmware.WEBOTS]
    batch = encode_batch(SENSORS, profile)
    request = encode_frame(MessageType.STEP, seq, batch.tx, 0x1234)
    frame = decode_frame(request)
    guard.check(frame.seq)
    guard.begin(frame.seq)
    parse_batch(frame.payload, profile)
    reply = encode_frame(MessageType.OK, frame.seq, batch_reply, frame.session)
    guard.done(frame.seq, reply)
    batch.decode(decode_frame(reply).payload)


class _SessionStep:
    """The step as it runs now: the request list packed, sealed with the session key (or a
    CRC), fed to the sans-I/O Session, its Run completed, the reply opened and decoded."""

    def __init__(self, sealed: bool) -> None:
        from ego.servers.sessions.actions import Peer, Run
        from ego.servers.sessions.session import Session

        secret = b"bench-secret-bench-secret" if sealed else None
        self.session = Session(
            secret=secret, deadline_s=0.5, chunk_size=16384, welcome=dict, udp_cookies=False
        )
        self.peer = Peer(("tcp", 1, None), "bench", "127.0.0.1")
        self.profile = PROFILES[Firmware.WEBOTS]
        self.run_type = Run
        raw = _handshake(self.session, self.peer, secret)
        self.client_key, self.sid = raw.key, raw.session
        self.server_key = self.session.key_for(self.sid)

    def __call__(self, batch_reply: bytes, seq: int) -> None:
        from ego.net.messages import pack_step

        batch = encode_batch(SENSORS, self.profile)
        request = encode_frame(
            MessageType.STEP, seq, pack_step(batch.requests), self.sid, self.client_key
        )
        frame = decode_frame(request, self.server_key)
        (run,) = self.session.receive(self.peer, frame, 0.0)
        assert isinstance(run, self.run_type)
        encode_batch(run.call.requests, self.profile)  # type: ignore[union-attr]
        (send,) = self.session.completed(self.sid, seq, batch_reply, 0.0)
        batch.decode(decode_frame(send.data, self.client_key).payload)  # type: ignore[union-attr]


def _handshake(session: object, peer: object, secret: bytes | None) -> object:
    """A completed handshake with ``session``, driven by hand: its key and session id."""
    from types import SimpleNamespace

    from ego.net.frames import Frame
    from ego.net.handshake import ClientHandshake

    shake = ClientHandshake(secret, "bench")
    (send,) = session.receive(peer, Frame(MessageType.HELLO, 1, shake.hello()), 0.0)  # type: ignore[attr-defined]
    challenge = decode_frame(send.data)
    proof = shake.answer(challenge.payload, challenge.session)
    session.receive(peer, Frame(MessageType.AUTH, 2, proof, challenge.session), 0.0)  # type: ignore[attr-defined]
    return SimpleNamespace(key=shake.key, session=challenge.session)


def cpu_table(iterations: int) -> Table:
    profile = PROFILES[Firmware.WEBOTS]
    batch = encode_batch(SENSORS, profile)
    reply = bytes(range(batch.reply_size))
    paths: dict[str, Any] = {
        "byte relay, CRC (the previous design)": None,
        "Session, CRC (loopback, no secret)": False,
        "Session, sealed (HMAC-SHA256 session key)": True,
    }
    results: dict[str, list[float]] = {name: [] for name in paths}
    for _ in range(5):  # interleaved, so that drifts of the machine hit every path alike
        for name, sealed in paths.items():
            if sealed is None:
                guard = SequenceGuard()
                start = time.process_time()
                for seq in range(1, iterations + 1):
                    _old_step(reply, guard, seq)
            else:
                step = _SessionStep(sealed)
                start = time.process_time()
                for seq in range(3, iterations + 3):
                    step(reply, seq)
            results[name].append((time.process_time() - start) / iterations * 1e6)

    # The same step's local part alone (what a direct link also does), for the share.
    start = time.process_time()
    for _ in range(iterations):
        encode_batch(SENSORS, profile).decode(reply)
    local = (time.process_time() - start) / iterations * 1e6
    table = Table(
        key="remote_cpu_overhead",
        title=f"CPU per full remote step without I/O (process_time, {iterations} steps x 5 runs)",
        columns=["path", "median [us]", "min", "max", "ratio to previous", "target [us]"],
    )
    old = sorted(results[next(iter(paths))])[2]
    for name, samples in results.items():
        samples.sort()
        table.rows.append([name, samples[2], samples[0], samples[-1], samples[2] / old, 100.0])
    table.rows.append(
        [
            "of which encode_batch + decode (a direct link's share too)",
            local,
            local,
            local,
            "-",
            "-",
        ]
    )
    table.notes.append(
        "Each path: the client's encoding and framing, the server's unframing, dedup and "
        "batch encoding, its reply's framing, the client's unframing and decoding."
    )
    return table


def run(quick: bool = False) -> list[Table]:
    return [
        roundtrip_table(20 if quick else 2000),
        cpu_table(2000 if quick else 20000),
    ]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="a smoke run: few steps")
    args = parser.parse_args(argv)
    for table in run(quick=args.quick):
        table.print()
    return 0


if __name__ == "__main__":
    sys.exit(main())
