"""Test doubles for the remote tests: a lossy UDP relay, a fake camera, a raw-socket client."""

from __future__ import annotations

import collections
import contextlib
import heapq
import itertools
import random
import select
import socket
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from types import TracebackType

from helpers import wait_until

from ego.backends.remote.channel import RemoteChannel
from ego.camera.source import GrantedFormat, PixelFormat
from ego.net.auth import client_proof, new_nonce
from ego.net.frames import (
    HEADER,
    MAC_SIZE,
    MAX_DATAGRAM,
    Frame,
    FrameKey,
    FrameReader,
    MessageType,
    decode_frame,
    encode_frame,
)
from ego.net.handshake import session_key
from ego.net.payloads import pack_json, unpack_json
from ego.net.urls import parse_url
from ego.serial.link import Link
from ego.servers.socket.server import Server
from ego.servers.socket.server_thread import ServerThread
from firmware_sim import Emulator


class DatagramProxy:
    """A UDP relay on loopback between one client and a server, with seeded mischief.

    Each datagram, either way, is dropped with probability ``drop``; else sent once, or
    twice with probability ``duplicate``; each copy has a bit flipped with probability
    ``corrupt`` and is held back up to ``max_delay_s`` with probability ``reorder``, so
    that later datagrams overtake it. The rates may change while it runs.
    """

    def __init__(
        self,
        target_url: str,
        *,
        seed: int = 0,
        drop: float = 0.0,
        duplicate: float = 0.0,
        reorder: float = 0.0,
        corrupt: float = 0.0,
        max_delay_s: float = 0.03,
    ) -> None:
        _, host, port = parse_url(target_url)
        self.drop, self.duplicate, self.reorder, self.corrupt = drop, duplicate, reorder, corrupt
        self.max_delay_s = max_delay_s
        self.rng = random.Random(seed)
        self.counts: collections.Counter[str] = collections.Counter()
        #: Every datagram received, either way, before any mischief.
        self.seen: list[bytes] = []
        #: The client's datagrams only, as they left it.
        self.up: list[bytes] = []
        self.front = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self.front.bind(("127.0.0.1", 0))
        self.back = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self.back.connect((host, port))
        self.client: tuple[str, int] | None = None
        self._queue: list[tuple[float, int, str, bytes]] = []
        self._order = itertools.count()
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, name="udp-proxy")

    @property
    def url(self) -> str:
        host, port = self.front.getsockname()
        return f"udp://{host}:{port}"

    def __enter__(self) -> DatagramProxy:
        self._thread.start()
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        self._stop.set()
        self._thread.join(timeout=5)
        self.front.close()
        self.back.close()
        assert not self._thread.is_alive(), "the proxy's thread did not end"

    def _run(self) -> None:
        while not self._stop.is_set():
            now = time.monotonic()
            timeout = 0.02 if not self._queue else max(0.0, self._queue[0][0] - now)
            readable, _, _ = select.select([self.front, self.back], [], [], min(timeout, 0.02))
            for sock in readable:
                try:
                    data, addr = sock.recvfrom(MAX_DATAGRAM)
                except OSError:
                    continue
                if sock is self.front:
                    self.client = addr
                    self._route(data, "up")
                else:
                    self._route(data, "down")
            now = time.monotonic()
            while self._queue and self._queue[0][0] <= now:
                _, _, direction, data = heapq.heappop(self._queue)
                self._send(direction, data)

    def inject(self, data: bytes) -> None:
        """Send ``data`` to the server from the client's address (as the server sees it):
        what an attacker on the path, or one spoofing the client's address, can do."""
        self.back.send(data)

    def _route(self, data: bytes, direction: str) -> None:
        self.seen.append(data)
        if direction == "up":
            self.up.append(data)
        rng = self.rng
        if rng.random() < self.drop:
            self.counts["dropped"] += 1
            return
        copies = 1
        if rng.random() < self.duplicate:
            copies = 2
            self.counts["duplicated"] += 1
        for _ in range(copies):
            out = data
            if rng.random() < self.corrupt:
                flipped = bytearray(data)
                bit = rng.randrange(len(flipped) * 8)
                flipped[bit // 8] ^= 1 << (bit % 8)
                out = bytes(flipped)
                self.counts["corrupted"] += 1
            delay = 0.0
            if rng.random() < self.reorder:
                delay = rng.uniform(0.001, self.max_delay_s)
                self.counts["delayed"] += 1
            when = time.monotonic() + delay
            heapq.heappush(self._queue, (when, next(self._order), direction, out))

    def _send(self, direction: str, data: bytes) -> None:
        with contextlib.suppress(OSError):
            if direction == "up":
                self.back.send(data)
            elif self.client is not None:
                self.front.sendto(data, self.client)


@dataclass
class FakeCamera:
    """A frame source whose every frame is distinct: its first 4 bytes count the frames."""

    opened: tuple[int, int, str] | None = None
    frames: int = 0
    controls: dict[str, int] = field(default_factory=dict)
    closed: int = 0
    #: Frames this many bytes long instead of the open size's (to test the size limit).
    frame_bytes: int | None = None

    def open(self, width: int, height: int, pixel_format: str) -> GrantedFormat:
        self.opened = (width, height, PixelFormat(pixel_format).value)
        return GrantedFormat(width, height, 2 * width)

    def expected(self, number: int) -> bytes:
        """Frame ``number`` (1, 2, ...) of the open size: a counter, then a pattern."""
        assert self.opened is not None
        width, height, _ = self.opened
        size = self.frame_bytes or width * height * 2
        head = number.to_bytes(4, "little")
        body = bytes((number * 7 + i) & 0xFF for i in range(251))
        return (head + body * (size // len(body) + 1))[:size]

    def read_frame(self) -> bytes:
        self.frames += 1
        return self.expected(self.frames)

    def set_control(self, name: str, value: int) -> int:
        granted = max(0, min(255, value))  # a camera clamps what it cannot do
        self.controls[name] = granted
        return granted

    def close(self) -> None:
        self.closed += 1
        self.opened = None


@dataclass
class Served:
    """An emulator, the server's link to it, and the server, on loopback."""

    emu: Emulator
    link: Link
    server: Server
    thread: ServerThread

    @property
    def url(self) -> str:
        return self.thread.url

    def url_of(self, kind: str) -> str:
        return next(u for u in self.thread.urls if u.startswith(kind))


class StreamRelay:
    """A TCP relay on loopback between one client and a server that can rewrite frames:
    ``rewrite(direction, index, frame) -> frame`` sees each whole frame ("up" to the
    server, "down" to the client, ``index`` counting from 0 per direction)."""

    def __init__(self, target_url: str, rewrite: Callable[[str, int, bytes], bytes]) -> None:
        _, host, port = parse_url(target_url)
        self.target = (host, port)
        self.rewrite = rewrite
        self.listener = socket.create_server(("127.0.0.1", 0))
        self.counts: collections.Counter[str] = collections.Counter()
        self._threads: list[threading.Thread] = []
        self._socks: list[socket.socket] = [self.listener]
        accept = threading.Thread(target=self._accept, name="relay-accept")
        accept.start()
        self._threads.append(accept)

    @property
    def url(self) -> str:
        return f"tcp://127.0.0.1:{self.listener.getsockname()[1]}"

    def _accept(self) -> None:
        with contextlib.suppress(OSError):
            while True:
                client, _ = self.listener.accept()
                server = socket.create_connection(self.target)
                self._socks += [client, server]
                for src, dst, direction in ((client, server, "up"), (server, client, "down")):
                    pump = threading.Thread(
                        target=self._pump, args=(src, dst, direction), name=f"relay-{direction}"
                    )
                    pump.start()
                    self._threads.append(pump)

    def _pump(self, src: socket.socket, dst: socket.socket, direction: str) -> None:
        buf = bytearray()
        index = 0
        with contextlib.suppress(OSError):
            while chunk := src.recv(1 << 16):
                buf += chunk
                while len(buf) >= HEADER.size:
                    type_, length = buf[3], int.from_bytes(buf[12:16], "little")
                    size = HEADER.size + length + (MAC_SIZE if type_ & 0x80 else 4)
                    if len(buf) < size:
                        break
                    frame, buf[:size] = bytes(buf[:size]), b""
                    out = self.rewrite(direction, index, frame)
                    if out != frame:
                        self.counts[f"rewritten {direction}"] += 1
                    index += 1
                    dst.sendall(out)
        with contextlib.suppress(OSError):
            dst.shutdown(socket.SHUT_WR)

    def close(self) -> None:
        """Close every socket (a shutdown first wakes a blocked accept or recv), then join
        every thread; one still running is a failure, not left behind."""
        for sock in self._socks:
            with contextlib.suppress(OSError):
                sock.shutdown(socket.SHUT_RDWR)
            with contextlib.suppress(OSError):
                sock.close()
        for thread in list(self._threads):
            thread.join(5)
        assert not any(t.is_alive() for t in self._threads), "a relay thread did not end"

    def __enter__(self) -> StreamRelay:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


class RawClient:
    """A hand-driven client speaking frames directly (for handshakes, attacks and garbage)."""

    def __init__(self, url: str, timeout_s: float = 2.0) -> None:
        scheme, host, port = parse_url(url)
        self.kind = scheme
        kind = socket.SOCK_STREAM if scheme == "tcp" else socket.SOCK_DGRAM
        self.sock = socket.socket(socket.AF_INET, kind)
        self.sock.settimeout(timeout_s)
        self.sock.connect((host, port))
        self.reader = FrameReader()
        self.session = 0
        self.seq = 0
        #: Once a secret's handshake is done: the key replies are opened and requests sealed with.
        self.key: FrameKey | None = None

    def send_raw(self, data: bytes) -> None:
        self.sock.sendall(data)

    def frame(self, mtype: MessageType, payload: bytes = b"", seq: int | None = None) -> bytes:
        self.seq = self.seq + 1 if seq is None else seq
        return encode_frame(mtype, self.seq, payload, self.session, self.key)

    def send(self, mtype: MessageType, payload: bytes = b"", seq: int | None = None) -> int:
        self.send_raw(self.frame(mtype, payload, seq))
        return self.seq

    def receive(self) -> Frame:
        """The next frame from the server (socket.timeout if none)."""
        while True:
            if self.kind == "udp":
                return decode_frame(self.sock.recv(MAX_DATAGRAM), self.key)
            chunk = self.sock.recv(1 << 16)
            if not chunk:
                raise ConnectionResetError("server closed the connection")
            frames = self.reader.feed(chunk)
            if frames:
                return frames[0]

    def hello(self, nonce: bytes) -> Frame:
        """HELLO (with the cookie a UDP server asks for); the server's challenge."""
        fields = {"client": "raw", "nonce": nonce.hex(), "pad": "-" * 400}
        self.send(MessageType.HELLO, pack_json(fields))
        reply = self.receive()
        if reply.type is MessageType.COOKIE:
            fields["cookie"] = unpack_json(reply.payload)["cookie"]
            self.send(MessageType.HELLO, pack_json(fields))
            reply = self.receive()
        self.session = reply.session
        return reply

    def handshake(self, secret: bytes | None = None, proof: bytes | None = None) -> Frame:
        """HELLO and AUTH: with ``secret``, its proof (then sealed frames); with ``proof``,
        that one (a guess) whatever the server proved; else an empty one. The reply."""
        nonce = new_nonce()
        challenge = self.hello(nonce)
        if challenge.type is not MessageType.OK:
            return challenge
        server_nonce = bytes.fromhex(unpack_json(challenge.payload)["nonce"])
        key = None
        if proof is None and secret is not None:
            proof = client_proof(secret, server_nonce, nonce, self.session)
            key = FrameKey(session_key(secret, nonce, server_nonce, self.session), server=False)
        self.reader.key = key
        self.key = None
        self.send(MessageType.AUTH, pack_json({"proof": (proof or b"").hex()}))
        self.key = key
        return self.receive()

    def close(self) -> None:
        self.sock.close()


#: How late the deadman may fire, at most, as a share of its deadline (README, "ego serve").
DEADMAN_MARGIN = 0.10


def assert_deadman_fired(server: Server, deadline_s: float, times: int = 1) -> float:
    """The server's deadman fired ``times`` times, the last after its client had been
    silent more than ``deadline_s`` and at most :data:`DEADMAN_MARGIN` more, on the
    server's own clock (what the test's loop saw later proves nothing); that silence."""
    stats = server.stats
    assert wait_until(lambda: len(stats.deadman_silences) >= times), stats
    assert stats.deadman_stops == times, stats
    silence = stats.deadman_silences[-1]
    assert deadline_s < silence <= deadline_s * (1 + DEADMAN_MARGIN), silence
    return silence


#: The ``serve`` and ``connect`` fixtures' types (in conftest.py), importable by tests.
ServeFactory = Callable[..., Served]
ConnectFactory = Callable[..., RemoteChannel]
