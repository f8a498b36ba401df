"""One client connection to ``ego serve``: socket, handshake, sealed requests and replies.

:class:`Connection` sends a request frame and waits for the reply with its sequence
number, stop-and-wait: over UDP it retransmits the same frame, a bounded number of
times, until the reply comes (the server answers a duplicate from its cache), and it
fetches a reply too big for one datagram slice by slice. Once the handshake is done
with a secret, every frame either way is sealed with the session key; a frame that
fails its MAC is dropped as forged, never taken for a reply. Errors the server
replied with are raised here as the ego error they name, with their fields.
"""

from __future__ import annotations

import logging
import socket
import time
from dataclasses import dataclass
from typing import Any

import ego.errors
from ego._version import __version__
from ego.errors import (
    EgoError,
    FrameError,
    LinkLostError,
    LinkTimeoutError,
    PortNotFoundError,
    RemoteError,
)
from ego.net.frames import (
    MAX_DATAGRAM,
    Frame,
    FrameKey,
    FrameReader,
    MessageType,
    decode_frame,
    encode_frame,
)
from ego.net.handshake import ClientHandshake
from ego.net.payloads import pack_fetch, unpack_error, unpack_json, unpack_part
from ego.net.sequence import next_seq

__all__ = ["Connection", "RemoteStats", "error_from_reply"]

log = logging.getLogger(__name__)

_ERROR_CLASSES: dict[str, type[EgoError]] = {
    name: cls
    for name, cls in vars(ego.errors).items()
    if isinstance(cls, type) and issubclass(cls, EgoError)
}
#: A UDP HELLO is padded to this, so that no reply to it is bigger (no amplification).
HELLO_PADDING = 480


def error_from_reply(payload: bytes, where: str) -> EgoError:
    """The ego error an ERROR reply names, with its attributes (RemoteError if unknown).

    Built without calling the class's constructor, whose arguments differ from class to
    class (ConfigSyntaxError takes a path and a line): the message and the attributes
    the server sent are set as they were.
    """
    name, message, fields = unpack_error(payload)
    cls = _ERROR_CLASSES.get(name, RemoteError)
    error = cls.__new__(cls)
    BaseException.__init__(error, f"{where}: {message}")
    for key, value in fields.items():
        if not key.startswith("_"):
            setattr(error, key, value)
    return error


@dataclass(slots=True)
class RemoteStats:
    """What the client did on the network, for logs, tests and benchmarks."""

    requests: int = 0
    retransmits: int = 0
    #: Replies to other requests (late or duplicated datagrams), discarded.
    stale: int = 0
    #: Datagrams that failed to decode (CRC, MAC...), discarded.
    corrupt: int = 0
    heartbeats: int = 0
    bytes_sent: int = 0
    bytes_received: int = 0


class Connection:
    """A socket to ``ego serve`` after a completed handshake (made at construction)."""

    def __init__(
        self,
        host: str,
        port: int,
        protocol: str,
        secret: bytes | None,
        *,
        connect_timeout_s: float = 2.0,
        retransmit_s: float = 0.02,
        retries: int = 8,
        stats: RemoteStats | None = None,
    ) -> None:
        self.protocol = protocol
        #: TCP and Unix sockets carry a stream of frames; UDP one frame a datagram.
        self.stream = protocol != "udp"
        shown = f"[{host}]" if ":" in host else host
        self.name = f"unix://{host}" if protocol == "unix" else f"{protocol}://{shown}:{port}"
        self.retransmit_s = retransmit_s
        self.retries = retries
        self.stats = stats or RemoteStats()
        self.deadline_s = 0.5
        self.session = 0
        self._seq = 0
        #: The session key: replies are opened with it, requests sealed with it (the
        #: AUTH itself goes unsealed: the server has no key until it checks the proof).
        self._key: FrameKey | None = None
        self._seal: FrameKey | None = None
        self._reader = FrameReader()
        self.welcome = self._open(host, port, secret, connect_timeout_s)

    def _open(
        self, host: str, port: int, secret: bytes | None, timeout_s: float
    ) -> dict[str, Any]:
        """Connect and shake hands within ``timeout_s``. A server under a flood of
        half-open connections hangs up the oldest one to make room (ego.servers.socket):
        a stream cut before the handshake ends is connected again, a fresh one, until the
        time is up; any other failure (no server, a wrong secret) is raised at once."""
        until = time.monotonic() + timeout_s
        while True:
            self._sock = self._connect(host, port, max(until - time.monotonic(), 0.05))
            try:
                return self._handshake(secret, max(until - time.monotonic(), 0.05))
            except (PortNotFoundError, LinkLostError) as exc:
                self.close()
                lost = exc if isinstance(exc, LinkLostError) else exc.__cause__
                cut = self.stream and isinstance(lost, LinkLostError)
                if not cut or time.monotonic() + 0.02 >= until:
                    raise
                log.info("%s: the connection was cut during the handshake (%s): again",
                         self.name, lost)  # fmt: skip
            except BaseException:
                self.close()
                raise
            time.sleep(0.02)
            self._reader = FrameReader()
            self._key = self._seal = None
            self.session = 0

    def _connect(self, host: str, port: int, timeout_s: float) -> socket.socket:
        kind = socket.SOCK_STREAM if self.stream else socket.SOCK_DGRAM
        try:
            addr: Any
            if self.protocol == "unix":
                family, addr = socket.AF_UNIX, host
            else:
                family, _, _, _, addr = socket.getaddrinfo(host, port, type=kind)[0]
            sock = socket.socket(family, kind)
        except OSError as exc:
            raise PortNotFoundError(f"cannot reach {self.name}: {exc}") from exc
        try:
            sock.settimeout(timeout_s)
            sock.connect(addr)  # for UDP: only the server's datagrams are received
            if kind == socket.SOCK_STREAM and family != socket.AF_UNIX:
                sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        except OSError as exc:
            sock.close()
            raise PortNotFoundError(f"no ego server at {self.name}: {exc}") from exc
        return sock

    def _handshake(self, secret: bytes | None, timeout_s: float) -> dict[str, Any]:
        shake = ClientHandshake(secret, self.name, f"ego {__version__}")
        try:
            reply = self._hello(shake, timeout_s)
            if reply.type is MessageType.COOKIE:  # UDP: prove we receive at our address
                shake.take_cookie(reply.payload)
                reply = self._hello(shake, timeout_s)
        except LinkTimeoutError as exc:
            why = str(exc).removeprefix(f"{self.name}: ")
            raise PortNotFoundError(f"no ego server answers at {self.name}: {why}") from exc
        except LinkLostError as exc:
            why = str(exc).removeprefix(f"{self.name}: ")
            raise PortNotFoundError(f"no ego server at {self.name}: {why}") from exc
        self.session = reply.session
        proof = shake.answer(self._payload(reply, MessageType.HELLO), self.session)
        self._key = self._reader.key = shake.key  # the welcome is the first sealed frame
        auth = self._roundtrip(MessageType.AUTH, proof, time.monotonic() + timeout_s, True)
        welcome = unpack_json(self._payload(auth, MessageType.AUTH))
        self._seal = shake.key
        self.deadline_s = float(welcome.get("deadline_s", self.deadline_s))
        return welcome

    def _hello(self, shake: ClientHandshake, timeout_s: float) -> Frame:
        payload = shake.hello()
        if self.protocol == "udp" and len(payload) < HELLO_PADDING:
            payload = payload[:-1] + b',"pad":"' + b"-" * (HELLO_PADDING - len(payload)) + b'"}'
        return self._roundtrip(MessageType.HELLO, payload, time.monotonic() + timeout_s, True)

    # -- requests ----------------------------------------------------------------------------

    def call(self, mtype: MessageType, payload: bytes = b"", timeout_s: float = 5.0) -> bytes:
        """One request; its OK payload, or the ego error the server replied with."""
        reply = self._roundtrip(mtype, payload, time.monotonic() + timeout_s)
        return self._payload(reply, mtype)

    def _payload(self, reply: Frame, mtype: MessageType) -> bytes:
        if reply.type is MessageType.ERROR:
            raise error_from_reply(reply.payload, self.name)
        if reply.type is not MessageType.OK:
            raise FrameError(f"{self.name}: unexpected {reply.type.name} reply to {mtype.name}")
        return reply.payload

    def _roundtrip(
        self, mtype: MessageType, payload: bytes, deadline: float, connecting: bool = False
    ) -> Frame:
        reply = self._exchange(mtype, payload, deadline, connecting)
        if reply.type is MessageType.PART:
            reply = self._fetch_rest(reply, deadline)
        return reply

    def _fetch_rest(self, first: Frame, deadline: float) -> Frame:
        """A reply that came in slices (UDP): FETCH the rest, one slice per request."""
        kind, total, offset, data = unpack_part(first.payload)
        if offset != 0:
            raise FrameError(f"{self.name}: a big reply starts at offset {offset}")
        buf = bytearray(data)
        while len(buf) < total:
            part = self._exchange(MessageType.FETCH, pack_fetch(first.seq, len(buf)), deadline)
            if part.type is MessageType.ERROR:
                raise error_from_reply(part.payload, self.name)
            if part.type is not MessageType.PART:
                raise FrameError(f"{self.name}: {part.type.name} reply to FETCH")
            kind2, total2, offset2, data2 = unpack_part(part.payload)
            if (kind2, total2, offset2) != (kind, total, len(buf)):
                raise FrameError(f"{self.name}: slice {offset2} of {total2}, expected {len(buf)}")
            buf += data2
        return Frame(kind, first.seq, bytes(buf), first.session)

    def _exchange(
        self, mtype: MessageType, payload: bytes, deadline: float, connecting: bool = False
    ) -> Frame:
        """Send one request frame (again, over UDP, until answered); its reply frame.
        A step's request is sent ``retries`` more times at most; the handshake's
        (``connecting``) until the connect timeout the caller gave: a server busy with a
        flood of HELLOs answers ours late, and getting in is what was asked."""
        self._seq = seq = next_seq(self._seq)
        data = encode_frame(mtype, seq, payload, self.session, self._seal)
        self.stats.requests += 1
        wait, attempts = self.retransmit_s, 0
        self._send(data)
        while True:
            limit = deadline if self.stream else min(deadline, time.monotonic() + wait)
            reply = self._receive(seq, limit)
            if reply is not None and reply.type is not MessageType.WORKING:
                return reply
            if time.monotonic() >= deadline:
                raise LinkTimeoutError(
                    f"{self.name}: no reply to {mtype.name} {seq} in time "
                    f"({attempts} retransmissions)"
                )
            if reply is not None:
                # WORKING: the server has the request and is running it (the serial line
                # may be retrying): keep waiting, up to the request timeout.
                wait, attempts = self.retransmit_s, 0
                continue
            if attempts >= self.retries and not connecting:
                raise LinkTimeoutError(
                    f"{self.name}: no reply to {mtype.name} {seq} after {attempts} retransmissions"
                )
            attempts += 1
            self.stats.retransmits += 1
            self._send(data)
            # Backing off, but never quieter than the heartbeat: the server would take a
            # silence beyond its deadline for a dead client.
            wait = min(wait * 2, self.deadline_s / 4)

    def _send(self, data: bytes) -> None:
        try:
            self._sock.sendall(data)
        except OSError as exc:
            told = self._last_word()
            raise told or LinkLostError(f"{self.name}: send failed: {exc}") from exc
        self.stats.bytes_sent += len(data)

    def _last_word(self) -> EgoError | None:
        """Why a server that hung up on a stream ended the session (its deadman...), if
        it said so before: still readable once sending fails."""
        if not self.stream:
            return None
        self._sock.setblocking(False)
        try:
            while chunk := self._sock.recv(1 << 16):
                for frame in self._reader.feed(chunk):
                    if frame.seq == 0 and frame.type is MessageType.ERROR:
                        return error_from_reply(frame.payload, self.name)
        except (OSError, FrameError):
            pass  # nothing more to read: the plain send failure it is
        return None

    def _receive(self, seq: int, until: float) -> Frame | None:
        """The reply to ``seq`` before ``until``, or None; other frames are discarded."""
        while True:
            remaining = until - time.monotonic()
            if remaining <= 0:
                return None
            self._sock.settimeout(remaining)
            try:
                chunk = self._sock.recv(1 << 16 if self.stream else MAX_DATAGRAM)
            except TimeoutError:
                return None
            except OSError as exc:  # ECONNREFUSED (UDP: nobody listens), ECONNRESET...
                raise LinkLostError(f"{self.name}: {exc}") from exc
            if not chunk and self.stream:
                raise LinkLostError(f"{self.name}: the server closed the connection")
            self.stats.bytes_received += len(chunk)
            try:
                frames = (
                    self._reader.feed(chunk) if self.stream else [decode_frame(chunk, self._key)]
                )
            except FrameError as exc:
                if self.stream:  # a stream cannot recover from a bad frame
                    raise LinkLostError(f"{self.name}: corrupt stream: {exc}") from exc
                self.stats.corrupt += 1
                log.debug("%s: dropped a corrupt or forged datagram: %s", self.name, exc)
                continue
            for frame in frames:
                if frame.seq == 0 and frame.type is MessageType.ERROR:
                    # Unsolicited: the server ended the session (deadman, shutdown).
                    raise error_from_reply(frame.payload, self.name)
                if frame.seq == seq and self.session in (0, frame.session):
                    return frame
                self.stats.stale += 1

    def close(self) -> None:
        self._sock.close()
