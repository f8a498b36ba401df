"""Abusive clients of ``ego serve``, for the tests and the security benchmark (issue 22).

* a controller that pipelines thousands of STEPs and closes its socket
  (:func:`pipeline_and_close`): how soon the wheels stand still, and how many batches
  the robot ran after the close;
* a socket that never hands shake and sends every kind of datagram
  (:func:`reflect_all`): how many bytes come back for each. After each datagram a padded
  HELLO serves as a marker: the server answers datagrams in order, so every reply
  before the marker's is the reply to the datagram under test.
"""

from __future__ import annotations

import secrets
import socket
import struct
import time
import zlib
from collections.abc import Iterator
from dataclasses import dataclass

from helpers import wait_until
from remote_helpers import RawClient

from ego.errors import FrameError
from ego.net.frames import (
    HEADER,
    MAGIC,
    MAX_DATAGRAM,
    PROTOCOL_VERSION,
    MessageType,
    decode_frame,
    encode_frame,
)
from ego.net.messages import pack_step
from ego.net.payloads import pack_json
from ego.net.urls import parse_url
from ego.seam.batch import Request
from ego.seam.profile import Command
from ego.servers.socket.server import Server
from firmware_sim import Emulator

#: Far more than one request in flight: what a pipelining controller writes at once.
PIPELINED = 3000
GO = pack_step((Request(Command.SET_SPEED, (300, 300)), Request(Command.GET_SPEED)))
#: A step that only reads the proximity sensors: its batch (letter N) is told apart from
#: GO's (D and E) in the emulator's history.
PROBE = pack_step((Request(Command.PROXIMITY),))


def drive(url: str, emu: Emulator, secret: str) -> RawClient:
    """A raw client that hands shake and authenticates with ``secret`` as the real client
    does, and drives the wheels at (300, 300)."""
    raw = RawClient(url, timeout_s=5.0)
    assert raw.handshake(secret.encode()).type is MessageType.OK
    raw.send(MessageType.STEP, GO)
    assert raw.receive().type is MessageType.OK
    assert emu.world.speeds == (300, 300)
    return raw


def pipeline_and_close(
    url: str, emu: Emulator, server: Server, secret: str, count: int = PIPELINED,
    budget_s: float = 1.0,
) -> tuple[float, int]:  # fmt: skip
    """Write ``count`` STEPs at once and close: (seconds until the wheels stood still,
    at most ``budget_s``; batches the robot saw after the close, before the first step
    of the next controller, which the server runs after anything left queued: one more
    in its ``stats.steps``)."""
    raw = drive(url, emu, secret)
    raw.send_raw(b"".join(raw.frame(MessageType.STEP, GO) for _ in range(count)))
    closed_at, seen = time.monotonic(), len(emu.history)
    raw.close()
    assert wait_until(lambda: emu.world.speeds == (0, 0), budget_s, 0.001)
    stopped_s = time.monotonic() - closed_at
    assert wait_until(lambda: server.controller is None)
    # Whatever was still queued would run before the next controller's first step (the
    # robot runs one step at a time, in the order they came): a probe's step ends the
    # count, however long the queue would take to run.
    probe = RawClient(url, timeout_s=5.0)
    assert probe.handshake(secret.encode()).type is MessageType.OK
    probe.send(MessageType.STEP, PROBE)
    assert probe.receive().type is MessageType.OK
    probe.send(MessageType.BYE)
    probe.close()
    after = [record.commands for record in list(emu.history)[seen:]]
    assert any("N" in letters for letters in after), after
    return stopped_s, next(i for i, letters in enumerate(after) if "N" in letters)


MARKER_SEQ = 0xFFFF0000


@dataclass(frozen=True)
class Probe:
    name: str
    sent: int
    answered: int

    @property
    def ratio(self) -> float:
        return self.answered / self.sent


def _frame(mtype: int, payload: bytes = b"", session: int = 0, seq: int = 1,
           version: int = PROTOCOL_VERSION) -> bytes:  # fmt: skip
    """A frame with a good CRC, of any type byte and version (encode_frame checks both)."""
    head = HEADER.pack(MAGIC, version, mtype, session, seq, len(payload))
    return head + payload + struct.pack("<I", zlib.crc32(head + payload))


def datagrams(controller: int, ended: int) -> Iterator[tuple[str, bytes]]:
    """Every kind of datagram an unproven peer can send, by name (``controller``: the
    session in control, ``ended``: one that ended)."""
    sessions = {"no session": 0, "unknown session": 0x5EC0_0001,
                "the controller's session": controller, "an ended session": ended}  # fmt: skip
    hello = pack_json({"client": "x", "nonce": secrets.token_bytes(32).hex()})
    for where, session in sessions.items():
        for mtype in MessageType:
            yield f"{mtype.name}, empty, {where}", _frame(mtype, b"", session)
        yield f"STEP, one request, {where}", _frame(MessageType.STEP, b"\xbb\x00", session)
        yield (
            f"AUTH with a proof, {where}",
            _frame(MessageType.AUTH, pack_json({"proof": bytes(32).hex()}), session),
        )
        yield f"FETCH, {where}", _frame(MessageType.FETCH, bytes(8), session)
        yield f"sealed PING, {where}", _frame(MessageType.PING | 0x80, bytes(12), session)
    yield "HELLO without a cookie", _frame(MessageType.HELLO, hello)
    yield (
        "HELLO with a forged cookie",
        _frame(MessageType.HELLO, hello[:-1] + b',"cookie":"' + bytes(16).hex().encode() + b'"}'),
    )
    yield "HELLO, not JSON", _frame(MessageType.HELLO, b"{nonce")
    yield "HELLO, nonce not hex", _frame(MessageType.HELLO, b'{"nonce":"zz"}')
    yield "AUTH, not JSON", _frame(MessageType.AUTH, b"[")
    yield "unknown type 0x3f", _frame(0x3F)
    yield "another protocol version", _frame(MessageType.PING, b"", 0, 1, PROTOCOL_VERSION + 7)
    yield "another version, a HELLO", _frame(MessageType.HELLO, hello, 0, 1, 9)
    yield "bad magic", b"XX" + _frame(MessageType.PING)[2:]
    yield "bad CRC", _frame(MessageType.PING)[:-1] + b"\x00"
    yield "length disagrees", _frame(MessageType.PING, b"ab")[:-5] + b"\x00\x00\x00\x00"
    yield "one byte", b"E"
    yield "empty", b""
    yield "garbage", secrets.token_bytes(64)
    whole = _frame(MessageType.HELLO, hello)
    for cut in (1, 4, 12, 15, 16, 19, 20, len(whole) - 1):
        yield f"HELLO truncated to {cut} bytes", whole[:cut]


class Reflector:
    """A socket that never hands shake: it sends one datagram, then a marker, and counts
    the bytes that come back before the marker's answer."""

    def __init__(self, url: str) -> None:
        _, host, port = parse_url(url)
        self.sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self.sock.settimeout(5.0)
        self.sock.connect((host, port))
        nonce = secrets.token_bytes(32).hex()
        marker = pack_json({"client": "marker", "nonce": nonce, "pad": "-" * 400})
        self.marker = encode_frame(MessageType.HELLO, MARKER_SEQ, marker)

    def probe(self, name: str, data: bytes) -> Probe:
        self.sock.send(data)
        self.sock.send(self.marker)
        answered = 0
        while True:
            reply = self.sock.recv(MAX_DATAGRAM)
            try:
                frame = decode_frame(reply)
            except FrameError:  # sealed for someone else, say: it counts all the same
                frame = None
            if frame is not None and frame.seq == MARKER_SEQ:
                assert frame.type is MessageType.COOKIE  # the marker never gets further
                return Probe(name, max(len(data), 1), answered)
            answered += len(reply)

    def close(self) -> None:
        self.sock.close()


def reflect_all(url: str, controller: int, ended: int) -> list[Probe]:
    reflector = Reflector(url)
    try:
        return [reflector.probe(name, data) for name, data in datagrams(controller, ended)]
    finally:
        reflector.close()
