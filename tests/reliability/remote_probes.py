"""Raw requests to ``ego serve`` for the bad-input table: what a pipelining controller and
a peer that never proved its address are told (issue 22)."""

from __future__ import annotations

import socket
import time

from ego.backends.remote.connection import Connection, error_from_reply
from ego.net.auth import coerce_secret
from ego.net.frames import MAX_DATAGRAM, MessageType, decode_frame, encode_frame
from ego.net.messages import pack_step
from ego.net.urls import parse_url
from ego.seam.batch import Request
from ego.seam.profile import Command

_STEP = pack_step((Request(Command.GET_SPEED),))


def pipelined(url: str, count: int, secret: str) -> None:
    """Hand shake with ``secret`` as the client does, write ``count`` STEPs at once, and
    raise the error the last one is answered with (nothing if it ran)."""
    _, host, port = parse_url(url)
    conn = Connection(host, port, "tcp", coerce_secret(secret))
    try:
        first = conn._seq + 1
        last = first + count - 1
        frames = [
            encode_frame(MessageType.STEP, seq, _STEP, conn.session, conn._seal)
            for seq in range(first, last + 1)
        ]
        conn._seq = last
        conn._send(b"".join(frames))
        reply = conn._receive(last, time.monotonic() + 2.0)
        conn.call(MessageType.BYE, b"", 1.0)
    finally:
        conn.close()
    if reply is not None and reply.type is MessageType.ERROR:
        raise error_from_reply(reply.payload, conn.name)


def udp_request(url: str, kind: str, session: int = 0, pad: int = 0) -> None:
    """One unsealed datagram of type ``kind`` (``pad`` bytes of payload) from a socket
    that never handed shake; raise the error it is answered with, or TimeoutError."""
    _, host, port = parse_url(url)
    data = encode_frame(MessageType[kind], 1, bytes(pad), session)
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as sock:
        sock.settimeout(0.5)
        sock.sendto(data, (host, port))
        try:
            reply = decode_frame(sock.recv(MAX_DATAGRAM))
        except TimeoutError:
            raise TimeoutError(f"no answer to a {len(data)}-byte {kind}") from None
    if reply.type is MessageType.ERROR:
        raise error_from_reply(reply.payload, url)
