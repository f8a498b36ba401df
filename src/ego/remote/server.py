"""``ego serve``: one controlling client drives the robot's serial link over TCP or UDP.

The server runs on the robot (or beside an emulator). It holds the :class:`~ego.serial.link.Link`
to the dsPIC and executes the controlling client's batches on it, one at a time, in a
worker thread, so that the asyncio loop stays free to watch the client:

* a batch is checked with :func:`~ego.serial.protocol.parse_batch` against the link's
  firmware profile before it goes near the robot; malformed or unsupported bytes are
  refused with an error frame;
* link errors (LinkTimeoutError, RobotResetError, ...) go back as error frames naming
  their class, which the client raises again;
* each session remembers its last request and reply (:class:`~ego.remote.wire.SequenceGuard`),
  so a retransmitted datagram is answered again and never runs twice;
* one client controls the robot at a time; a second one is told who has it;
* if the controlling client is silent for longer than ``deadline_s`` (it sends a
  heartbeat while idle) or disconnects, the motors stop and the LEDs go off.

Off loopback the server insists on a shared secret (:mod:`ego.remote.auth`).

>>> server = RemoteServer(link, listen="tcp://127.0.0.1:4242")   # doctest: +SKIP
>>> with ServerThread(server) as running:                          # doctest: +SKIP
...     print(running.urls)
"""

from __future__ import annotations

import abc
import asyncio
import collections
import concurrent.futures
import contextlib
import logging
import secrets
import threading
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from types import TracebackType
from typing import TYPE_CHECKING, Any, Literal, cast

from ego import __version__
from ego.errors import (
    AuthenticationError,
    CameraError,
    EgoError,
    FrameError,
    LinkLostError,
    ProtocolError,
    RemoteError,
    RobotBusyError,
    UnsupportedDeviceError,
    VersionMismatchError,
)
from ego.remote.auth import (
    NONCE_SIZE,
    FailureThrottle,
    check_proof,
    client_proof,
    coerce_secret,
    is_loopback,
    new_nonce,
    server_proof,
)
from ego.remote.wire import (
    DEFAULT_CHUNK_SIZE,
    MAX_DATAGRAM,
    MAX_PAYLOAD,
    OVERHEAD,
    PROTOCOL_VERSION,
    REQUEST_TYPES,
    Frame,
    FrameReader,
    MessageType,
    SequenceGuard,
    Verdict,
    decode_frame,
    encode_frame,
    error_fields,
    pack_error,
    pack_json,
    parse_url,
    split_reply,
    unpack_ascii,
    unpack_fetch,
    unpack_json,
)
from ego.safety import send_stop
from ego.serial.link import Link
from ego.serial.protocol import parse_batch

if TYPE_CHECKING:
    from ego.camera.source import FrameSource

__all__ = [
    "DEFAULT_DEADLINE_S",
    "DEFAULT_LISTEN",
    "FrameEncoder",
    "RemoteServer",
    "ServerStats",
    "ServerThread",
    "check_listen",
    "encode_image",
]

log = logging.getLogger(__name__)

DEFAULT_LISTEN = "tcp://127.0.0.1:4242"
#: How long the controlling client may stay silent before the robot is stopped.
DEFAULT_DEADLINE_S = 0.5
#: Handshakes started (HELLO) but not finished (AUTH) that the server remembers.
_MAX_PENDING = 16
#: Ended sessions remembered, so that their late requests get a clear "expired".
_MAX_EXPIRED = 64


#: ``(raw, width, height, stride, pixel_format, kind, quality, rotation) -> bytes``: a raw
#: frame as a JPEG or PNG file's bytes.
FrameEncoder = Callable[[bytes, int, int, int, str, str, int, int], bytes]


def encode_image(
    raw: bytes,
    width: int,
    height: int,
    stride: int,
    pixel_format: str,
    kind: str,
    quality: int,
    rotation: int,
) -> bytes:
    """A raw frame (RGB565, RGB565_BE or YUYV) as JPEG (``quality`` 1..100) or PNG.

    The camera package converts and rotates it (``rotation`` 180 undoes the e-puck
    camera's mounting), exactly as a client's Camera would.
    """
    from ego.camera import encode_jpeg, encode_png, rgb565_to_rgb888, yuyv_to_rgb888
    from ego.camera.source import PixelFormat

    fmt = PixelFormat(pixel_format)
    if fmt is PixelFormat.YUYV:
        image = yuyv_to_rgb888(raw, width, height, rotation, stride_bytes=stride)
    else:
        order: Literal["little", "big"] = "big" if fmt is PixelFormat.RGB565_BE else "little"
        image = rgb565_to_rgb888(raw, width, height, rotation, order, stride_bytes=stride)
    if kind == "jpeg":
        return encode_jpeg(image, quality)
    if kind == "png":
        return encode_png(image)
    raise CameraError(f"image kind {kind!r} is not jpeg or png")


@dataclass(slots=True)
class ServerStats:
    """What the server did, for logs, tests and benchmarks."""

    requests: int = 0
    steps: int = 0
    #: Retransmitted requests answered from the cache, without running them again.
    repeats: int = 0
    #: Requests older than the last one (late duplicates), ignored.
    stale: int = 0
    #: Frames that failed to decode (bad magic, CRC, size...).
    malformed: int = 0
    #: Handshakes refused (wrong secret, robot busy, wrong version).
    refused: int = 0
    sessions: int = 0
    #: Times the robot was stopped because its client went silent or away.
    deadman_stops: int = 0
    #: TCP connections dropped unheard: over the half-open cap, or never in control in
    #: time (a slow or idle handshake).
    dropped: int = 0
    errors: collections.Counter[str] = field(default_factory=collections.Counter)


def check_listen(
    listen: Sequence[str], secret: bytes | None, require_secret: bool = False
) -> list[tuple[str, str, int]]:
    """The (scheme, host, port) of each listen URL; ValueError for a bad URL, or for an
    address off loopback (or ``require_secret``) without a shared secret."""
    if not listen:
        raise ValueError("nothing to listen on")
    endpoints = [parse_url(url) for url in listen]
    off_loopback = [f"{s}://{h}:{p}" for s, h, p in endpoints if not is_loopback(h)]
    if secret is None and (require_secret or off_loopback):
        where = ", ".join(off_loopback) or "this server"
        raise ValueError(
            f"{where} is reachable from other machines: give a shared secret "
            "(ego serve --secret-file FILE) or listen on 127.0.0.1"
        )
    return endpoints


#: Half-open TCP connections kept at once: far more than honest clients (one controller,
#: a few refused), far fewer than the 1024 file descriptors a process usually has.
MAX_UNAUTHENTICATED = 64


class _Peer(abc.ABC):
    """Where replies go: a TCP connection, or a UDP address."""

    def __init__(self, key: object, label: str, max_datagram: int | None, host: str) -> None:
        self.key = key
        self.label = label
        #: The address it comes from, for the per-source brake on guessing.
        self.host = host
        #: Replies bigger than this go out in PARTs (None: a stream, no limit).
        self.max_datagram = max_datagram

    @abc.abstractmethod
    def send(self, data: bytes) -> None:
        """Send one frame's bytes to this peer."""

    def close(self) -> None:  # noqa: B027 - deliberately empty: a datagram peer holds nothing
        """Drop the connection (nothing to do for a datagram peer)."""


class _TcpPeer(_Peer):
    def __init__(self, transport: asyncio.Transport) -> None:
        addr = transport.get_extra_info("peername")
        label = f"tcp {addr[0]}:{addr[1]}" if isinstance(addr, tuple) else "tcp ?"
        host = str(addr[0]) if isinstance(addr, tuple) else "?"
        super().__init__(("tcp", id(transport)), label, None, host)
        self.transport = transport

    def send(self, data: bytes) -> None:
        if not self.transport.is_closing():
            self.transport.write(data)

    def close(self) -> None:
        self.transport.close()


class _UdpPeer(_Peer):
    def __init__(self, transport: asyncio.DatagramTransport, addr: Any, chunk: int) -> None:
        super().__init__(("udp", addr), f"udp {addr[0]}:{addr[1]}", chunk, str(addr[0]))
        self.transport = transport
        self.addr = addr

    def send(self, data: bytes) -> None:
        if not self.transport.is_closing():
            self.transport.sendto(data, self.addr)


class _Session:
    """One client's handshake, then (once authenticated) its control of the robot."""

    def __init__(self, peer: _Peer, session_id: int, client_nonce: bytes, hello: Frame) -> None:
        self.peer = peer
        self.id = session_id
        self.client_nonce = client_nonce
        self.server_nonce = new_nonce()
        self.hello = hello
        self.guard = SequenceGuard()
        self.created = self.last_heard = time.monotonic()
        self.busy = 0
        self.lock = asyncio.Lock()
        #: The last reply too big for one datagram, for FETCH: (seq, type, payload).
        self.big: tuple[int, MessageType, bytes] | None = None
        #: (width, height, stride, pixel format) once the client opened the camera.
        self.camera: tuple[int, int, int, str] | None = None


class _TcpProtocol(asyncio.Protocol):
    def __init__(self, server: RemoteServer) -> None:
        self.server = server
        self.reader = FrameReader()
        self.peer: _TcpPeer | None = None

    def connection_made(self, transport: asyncio.BaseTransport) -> None:
        assert isinstance(transport, asyncio.Transport)
        self.peer = _TcpPeer(transport)
        server = self.server
        if len(server.half_open) >= server.max_unauthenticated:
            # More half-open connections than any real client needs: the oldest goes,
            # quietly. A flood then churns through its own sockets, while a client's
            # handshake, a millisecond long, completes between two evictions.
            _, oldest = server.half_open.popitem(last=False)
            server.stats.dropped += 1
            oldest.abort()
        server.half_open[self.peer.key] = transport
        # A connection that has not become the controller in time is dropped (slowloris).
        asyncio.get_running_loop().call_later(server.handshake_timeout_s, self._expire)

    def _expire(self) -> None:
        peer = self.peer
        if peer is not None and not self.server.controls(peer) and not peer.transport.is_closing():
            self.server.stats.dropped += 1
            peer.close()

    def data_received(self, data: bytes) -> None:
        assert self.peer is not None
        try:
            frames = self.reader.feed(data)
        except FrameError as exc:
            # A stream with a bad frame cannot be resynchronised: say why, hang up.
            self.server.malformed(self.peer, exc)
            self.peer.close()
            return
        for frame in frames:
            self.server.frame_received(self.peer, frame)

    def connection_lost(self, exc: Exception | None) -> None:
        if self.peer is not None:
            self.server.half_open.pop(self.peer.key, None)
            self.server.peer_lost(self.peer)


class _UdpProtocol(asyncio.DatagramProtocol):
    def __init__(self, server: RemoteServer) -> None:
        self.server = server
        self.transport: asyncio.DatagramTransport | None = None

    def connection_made(self, transport: asyncio.BaseTransport) -> None:
        # The selector loop's datagram transport is not registered as a DatagramTransport.
        self.transport = cast(asyncio.DatagramTransport, transport)

    def datagram_received(self, data: bytes, addr: Any) -> None:
        assert self.transport is not None
        peer = _UdpPeer(self.transport, addr, self.server.chunk_size)
        try:
            frame = decode_frame(data)
        except VersionMismatchError as exc:
            self.server.malformed(peer, exc)
            return
        except FrameError as exc:
            # Garbage gets no answer over UDP (a corrupted datagram is retransmitted by
            # its sender; answering forged ones would make us an amplifier).
            self.server.stats.malformed += 1
            log.debug("%s: dropped a malformed datagram: %s", peer.label, exc)
            return
        self.server.frame_received(peer, frame)

    def error_received(self, exc: Exception) -> None:
        log.debug("UDP error (a client went away?): %s", exc)


class RemoteServer:
    """Serves one robot's link (and camera) to one controlling client at a time.

    ``listen`` is one or more ``tcp://HOST:PORT`` / ``udp://HOST:PORT`` (port 0 picks a
    free port; :attr:`urls` tells which). ``secret`` is the shared secret; it is required
    when listening off loopback or when ``require_secret`` is true. The server does not
    own ``link``: whoever opened it closes it after :meth:`aclose`.
    """

    def __init__(
        self,
        link: Link,
        *,
        listen: str | Sequence[str] = DEFAULT_LISTEN,
        secret: str | bytes | None = None,
        require_secret: bool = False,
        deadline_s: float = DEFAULT_DEADLINE_S,
        frame_source: FrameSource | None = None,
        frame_encoder: FrameEncoder = encode_image,
        chunk_size: int = DEFAULT_CHUNK_SIZE,
        handshake_timeout_s: float = 2.0,
        auth_failure_delay_s: float = 0.2,
    ) -> None:
        self.link = link
        self.listen = [listen] if isinstance(listen, str) else list(listen)
        self.secret = coerce_secret(secret)
        self._endpoints = check_listen(self.listen, self.secret, require_secret)
        if deadline_s <= 0:
            raise ValueError(f"deadline {deadline_s} s must be positive")
        if not OVERHEAD + 1024 <= chunk_size <= MAX_DATAGRAM:
            raise ValueError(
                f"chunk size {chunk_size} is outside {OVERHEAD + 1024}..{MAX_DATAGRAM}"
            )
        self.deadline_s = deadline_s
        self.frame_source = frame_source
        self.frame_encoder = frame_encoder
        self.chunk_size = chunk_size
        self.handshake_timeout_s = handshake_timeout_s
        #: TCP connections open but not (yet) in control, oldest first; beyond the cap
        #: the oldest is dropped.
        self.half_open: collections.OrderedDict[object, asyncio.Transport] = (
            collections.OrderedDict()
        )
        self.max_unauthenticated = MAX_UNAUTHENTICATED
        self.auth_failure_delay_s = auth_failure_delay_s
        self._throttle = FailureThrottle(base_s=auth_failure_delay_s)
        #: Wrong proofs are answered one at a time (see FailureThrottle).
        self._failure_lock: asyncio.Lock | None = None
        self.stats = ServerStats()
        self.urls: list[str] = []
        self._controller: _Session | None = None
        self._pending: collections.OrderedDict[object, _Session] = collections.OrderedDict()
        self._expired: collections.OrderedDict[int, str] = collections.OrderedDict()
        self._tasks: set[asyncio.Task[None]] = set()
        self._closers: list[Callable[[], None]] = []
        self._watchdog: asyncio.Task[None] | None = None
        self._closed = asyncio.Event()
        self._stopped = False
        # The serial line is blocking and must be used by one thread: one worker for it,
        # another for the camera so a slow capture never delays a step.
        self._link_thread = concurrent.futures.ThreadPoolExecutor(1, "ego-serve-link")
        self._camera_thread = concurrent.futures.ThreadPoolExecutor(1, "ego-serve-camera")

    @property
    def auth_required(self) -> bool:
        return self.secret is not None

    @property
    def controller(self) -> str | None:
        """Who controls the robot now ("tcp 127.0.0.1:50312"), or None."""
        return self._controller.peer.label if self._controller else None

    def controls(self, peer: _Peer) -> bool:
        """Whether ``peer`` is the client that controls the robot."""
        return self._controller is not None and self._controller.peer.key == peer.key

    # -- lifecycle -------------------------------------------------------------------------

    async def start(self) -> None:
        """Bind every listen address and start the deadman watchdog."""
        loop = asyncio.get_running_loop()
        for scheme, host, port in self._endpoints:
            if scheme == "tcp":
                server = await loop.create_server(lambda: _TcpProtocol(self), host, port)
                sockname = server.sockets[0].getsockname()
                self._closers.append(server.close)
            else:
                transport, _ = await loop.create_datagram_endpoint(
                    lambda: _UdpProtocol(self), local_addr=(host, port)
                )
                sockname = transport.get_extra_info("sockname")
                self._closers.append(transport.close)
            shown = f"[{sockname[0]}]" if ":" in sockname[0] else sockname[0]
            self.urls.append(f"{scheme}://{shown}:{sockname[1]}")
        self._watchdog = loop.create_task(self._watch())
        log.info(
            "serving %s (%s firmware) on %s%s",
            self.link.transport.name,
            self.link.profile.firmware,
            ", ".join(self.urls),
            " (shared secret required)" if self.auth_required else "",
        )

    async def serve_forever(self) -> None:
        """Serve until :meth:`aclose` (start first if not started)."""
        if not self.urls:
            await self.start()
        await self._closed.wait()

    async def aclose(self) -> None:
        """Stop the robot if someone controls it, then stop listening; idempotent."""
        if self._stopped:
            return
        self._stopped = True
        if self._controller is not None:
            await self._end_session(self._controller, "the server is shutting down", notify=True)
        for close in self._closers:
            close()
        if self._watchdog is not None:
            self._watchdog.cancel()
            with contextlib.suppress(asyncio.CancelledError):
                await self._watchdog
        for task in list(self._tasks):
            task.cancel()
        self._link_thread.shutdown(wait=True)
        self._camera_thread.shutdown(wait=True)
        self._closed.set()

    # -- frames in -------------------------------------------------------------------------

    def malformed(self, peer: _Peer, exc: FrameError) -> None:
        """A frame that cannot be used: count it, tell the peer why (it may be confused)."""
        self.stats.malformed += 1
        log.info("%s: malformed frame: %s", peer.label, exc)
        seq, session = (exc.seq, exc.session) if isinstance(exc, VersionMismatchError) else (0, 0)
        name = "RemoteError" if isinstance(exc, VersionMismatchError) else "FrameError"
        message = str(exc)
        if isinstance(exc, VersionMismatchError):
            message = (
                f"this ego server speaks remote protocol version "
                f"{PROTOCOL_VERSION} and the client {exc.peer_version}: "
                "install the same ego version on both ends"
            )
        peer.send(encode_frame(MessageType.ERROR, seq, pack_error(name, message), session))

    def frame_received(self, peer: _Peer, frame: Frame) -> None:
        self.stats.requests += 1
        if frame.type not in REQUEST_TYPES:
            self._send_error(peer, frame, FrameError(f"{frame.type.name} is not a request"))
            return
        task = asyncio.ensure_future(self._serve(peer, frame))
        self._tasks.add(task)
        task.add_done_callback(self._tasks.discard)

    def peer_lost(self, peer: _Peer) -> None:
        """A TCP connection closed: a controller that did not say goodbye is stopped."""
        self._pending.pop(peer.key, None)
        session = self._controller
        if session is not None and session.peer.key == peer.key:
            task = asyncio.ensure_future(self._end_session(session, "disconnected"))
            self._tasks.add(task)
            task.add_done_callback(self._tasks.discard)

    def _send_error(self, peer: _Peer, frame: Frame, exc: Exception) -> None:
        self.stats.errors[type(exc).__name__] += 1
        payload = pack_error(type(exc).__name__, str(exc), error_fields(exc))
        peer.send(encode_frame(MessageType.ERROR, frame.seq, payload, frame.session))

    async def _serve(self, peer: _Peer, frame: Frame) -> None:
        try:
            if frame.type is MessageType.HELLO:
                self._hello(peer, frame)
            elif frame.type is MessageType.AUTH:
                await self._auth(peer, frame)
            else:
                await self._request(peer, frame)
        except Exception:  # one bad request must never take the server down
            log.exception("%s: internal error serving %s", peer.label, frame.type.name)

    # -- handshake -------------------------------------------------------------------------

    def _hello(self, peer: _Peer, frame: Frame) -> None:
        pending = self._pending.get(peer.key)
        if pending is not None and pending.hello == frame:
            peer.send(pending.guard.cached)  # a retransmitted HELLO: the same challenge
            return
        busy = self._controller
        if busy is not None and busy.peer.key == peer.key and busy.hello == frame:
            return  # a late duplicate of the controller's own HELLO
        try:
            hello = unpack_json(frame.payload)
            client_nonce = bytes.fromhex(str(hello["nonce"]))
            if len(client_nonce) != NONCE_SIZE:
                raise ValueError(f"nonce of {len(client_nonce)} bytes, expected {NONCE_SIZE}")
        except (FrameError, KeyError, ValueError) as exc:
            self._send_error(peer, frame, FrameError(f"malformed HELLO: {exc}"))
            return
        if busy is not None:
            self.stats.refused += 1
            log.info("%s: refused, the robot is controlled by %s", peer.label, busy.peer.label)
            self._send_error(
                peer,
                frame,
                RobotBusyError(
                    f"the robot is already controlled by {self._who(busy)} (one client at a time)"
                ),
            )
            return
        session = _Session(peer, self._new_session_id(), client_nonce, frame)
        reply = {
            "nonce": session.server_nonce.hex(),
            "auth": self.auth_required,
            "deadline_s": self.deadline_s,
            "server": f"ego {__version__}",
        }
        data = encode_frame(MessageType.OK, frame.seq, pack_json(reply), session.id)
        session.guard.done(frame.seq, data)
        self._pending[peer.key] = session
        while len(self._pending) > _MAX_PENDING:
            self._pending.popitem(last=False)
        peer.send(data)

    async def _auth(self, peer: _Peer, frame: Frame) -> None:
        owner = self._controller
        if owner is not None and owner.peer.key == peer.key and owner.id == frame.session:
            owner.last_heard = time.monotonic()
            if owner.guard.check(frame.seq) is Verdict.REPEAT:
                peer.send(owner.guard.cached)  # the welcome was lost: say it again
            return
        session = self._pending.get(peer.key)
        if session is None or session.id != frame.session:
            self._send_error(
                peer,
                frame,
                AuthenticationError("no handshake in progress for this session: connect again"),
            )
            return
        verdict = session.guard.check(frame.seq)
        if verdict is not Verdict.NEW:
            if verdict is Verdict.REPEAT:
                peer.send(session.guard.cached)
            elif verdict is Verdict.WORKING:  # a retransmission while a wrong proof is held
                peer.send(encode_frame(MessageType.WORKING, frame.seq, b"", session.id))
            return
        session.guard.begin(frame.seq)
        try:
            proof = bytes.fromhex(str(unpack_json(frame.payload)["proof"]))
        except (FrameError, KeyError, ValueError) as exc:
            self._pending.pop(peer.key, None)
            self._send_error(peer, frame, FrameError(f"malformed AUTH: {exc}"))
            return
        if self.secret is not None:
            expected = client_proof(
                self.secret, session.server_nonce, session.client_nonce, session.id
            )
            if not check_proof(expected, proof):
                self.stats.refused += 1
                log.warning("%s: refused, wrong shared secret", peer.label)
                delay = self._throttle.failed(peer.host, time.monotonic())
                if self._failure_lock is None:
                    self._failure_lock = asyncio.Lock()
                async with self._failure_lock:  # one failure answered at a time, in all
                    await asyncio.sleep(delay)
                # Forgotten only now: a UDP retransmission meanwhile is told WORKING, not
                # "no handshake in progress", so the client learns the real reason.
                if self._pending.get(peer.key) is session:
                    del self._pending[peer.key]
                self._send_error(
                    peer,
                    frame,
                    AuthenticationError(
                        "wrong shared secret" if proof else "this server requires a shared secret"
                    ),
                )
                peer.close()
                return
        self._pending.pop(peer.key, None)
        if self._controller is not None:
            self.stats.refused += 1
            self._send_error(
                peer,
                frame,
                RobotBusyError(f"the robot is already controlled by {self._who(self._controller)}"),
            )
            return
        info = self.link.info
        welcome = {
            "proof": (
                server_proof(
                    self.secret, session.client_nonce, session.server_nonce, session.id
                ).hex()
                if self.secret is not None
                else ""
            ),
            "firmware": str(info.firmware),
            "firmware_version": info.version,
            "deadline_s": self.deadline_s,
            "chunk_size": self.chunk_size,
            "camera": self.frame_source is not None,
        }
        data = encode_frame(MessageType.OK, frame.seq, pack_json(welcome), session.id)
        session.guard.done(frame.seq, data)
        session.last_heard = time.monotonic()
        self._controller = session
        self.half_open.pop(peer.key, None)  # in control: never dropped as half-open
        self.stats.sessions += 1
        log.info("%s controls the robot (session %08x)", peer.label, session.id)
        peer.send(data)

    def _who(self, session: _Session) -> str:
        """The controller, as told to a refused client: its address only where anyone may
        connect anyway (with a secret, a stranger learns nothing)."""
        return "another client" if self.auth_required else session.peer.label

    def _new_session_id(self) -> int:
        while True:
            sid = secrets.randbits(32)
            if sid and sid not in self._expired:
                return sid

    # -- requests of the controlling client ------------------------------------------------

    async def _request(self, peer: _Peer, frame: Frame) -> None:
        session = self._controller
        if session is None or session.peer.key != peer.key or session.id != frame.session:
            if frame.type is MessageType.BYE:  # saying goodbye twice is fine
                peer.send(encode_frame(MessageType.OK, frame.seq, b"", frame.session))
                return
            why = self._expired.get(frame.session)
            message = (
                f"session ended: {why}; the robot was stopped"
                if why
                else "no such session on this server: connect first"
            )
            self._send_error(peer, frame, LinkLostError(message))
            return
        session.last_heard = time.monotonic()
        if not self._answer_known(session, frame):
            return
        async with session.lock:
            if session is not self._controller or not self._answer_known(session, frame):
                return
            session.guard.begin(frame.seq)
            session.busy += 1
            try:
                reply_type, payload = await self._execute(session, frame)
            finally:
                session.busy -= 1
                session.last_heard = time.monotonic()
            data = self._reply_bytes(session, frame.seq, reply_type, payload)
            session.guard.done(frame.seq, data)
        if frame.type is MessageType.BYE:
            # Stopped before the reply goes: when close() returns, the robot stands still.
            await self._end_session(session, "said goodbye", level=logging.INFO)
        peer.send(data)

    def _answer_known(self, session: _Session, frame: Frame) -> bool:
        """True if ``frame`` is new; else answer a duplicate from the cache and say False."""
        verdict = session.guard.check(frame.seq)
        if verdict is Verdict.NEW:
            return True
        if verdict is Verdict.REPEAT:
            self.stats.repeats += 1
            session.peer.send(session.guard.cached)
        elif verdict is Verdict.WORKING:
            session.peer.send(encode_frame(MessageType.WORKING, frame.seq, b"", session.id))
        else:
            self.stats.stale += 1
        return False

    def _reply_bytes(
        self, session: _Session, seq: int, reply_type: MessageType, payload: bytes
    ) -> bytes:
        limit = session.peer.max_datagram
        if limit is None or OVERHEAD + len(payload) <= limit:
            return encode_frame(reply_type, seq, payload, session.id)
        session.big = (seq, reply_type, payload)
        part = split_reply(reply_type, payload, 0, limit)
        return encode_frame(MessageType.PART, seq, part, session.id)

    async def _execute(self, session: _Session, frame: Frame) -> tuple[MessageType, bytes]:
        """Run one request; errors become an ERROR reply naming their ego class."""
        try:
            payload, reply_type = await self._dispatch(session, frame), MessageType.OK
            if frame.type is MessageType.FETCH:
                reply_type = MessageType.PART
            if len(payload) > MAX_PAYLOAD:
                raise RemoteError(
                    f"reply of {len(payload)} bytes exceeds the {MAX_PAYLOAD}-byte frame limit"
                )
            return reply_type, payload
        except EgoError as exc:
            self.stats.errors[type(exc).__name__] += 1
            if not isinstance(exc, FrameError | ProtocolError | UnsupportedDeviceError):
                log.warning("%s: %s failed: %s", session.peer.label, frame.type.name, exc)
            return MessageType.ERROR, pack_error(type(exc).__name__, str(exc), error_fields(exc))
        except Exception as exc:
            self.stats.errors["internal"] += 1
            log.exception("%s: %s failed", session.peer.label, frame.type.name)
            return MessageType.ERROR, pack_error("RemoteError", f"internal server error: {exc!r}")

    async def _dispatch(self, session: _Session, frame: Frame) -> bytes:
        loop = asyncio.get_running_loop()
        mtype = frame.type
        if mtype is MessageType.STEP:
            self.stats.steps += 1
            return await loop.run_in_executor(self._link_thread, self._step, frame.payload)
        if mtype is MessageType.ASCII:
            letter, lines = unpack_ascii(frame.payload)
            replies = await loop.run_in_executor(
                self._link_thread, self.link.ascii_command, letter, lines
            )
            return "".join(line + "\r\n" for line in replies).encode("ascii", "replace")
        if mtype in (MessageType.PING, MessageType.BYE):
            return b""
        if mtype is MessageType.FETCH:
            seq, offset = unpack_fetch(frame.payload)
            if session.big is None or session.big[0] != seq:
                raise FrameError(f"no big reply to request {seq} to fetch from")
            limit = session.peer.max_datagram or self.chunk_size
            return split_reply(session.big[1], session.big[2], offset, limit)
        return await self._camera(session, mtype, frame.payload)

    def _step(self, tx: bytes) -> bytes:
        """One client batch on the robot (in the link thread)."""
        try:
            batch = parse_batch(tx, self.link.profile)
        except ValueError as exc:
            if isinstance(exc.__cause__, UnsupportedDeviceError):
                raise UnsupportedDeviceError(f"batch refused: {exc.__cause__}") from exc
            raise ProtocolError(f"batch refused: {exc}") from exc
        return self.link.exchange(batch)

    async def _camera(self, session: _Session, mtype: MessageType, payload: bytes) -> bytes:
        source = self.frame_source
        if source is None:
            raise CameraError("this ego server has no camera")
        from ego.camera.source import FieldOfViewControl, PixelFormat

        loop = asyncio.get_running_loop()
        run = self._camera_thread
        if mtype is MessageType.CAMERA_CLOSE:
            session.camera = None
            await loop.run_in_executor(run, source.close)
            return b""
        request = unpack_json(payload)
        if mtype is MessageType.CAMERA_OPEN:
            width, height = request.get("width"), request.get("height")
            if not (isinstance(width, int) and isinstance(height, int)):
                raise FrameError(f"CAMERA_OPEN needs an integer width and height: {request}")
            try:
                fmt = PixelFormat(request.get("pixel_format"))
            except ValueError as exc:
                raise CameraError(f"unknown pixel format: {exc}") from exc
            got = await loop.run_in_executor(run, source.open, width, height, fmt)
            session.camera = (got[0], got[1], got[2], fmt.value)
            return pack_json({"width": got[0], "height": got[1], "stride": got[2]})
        if mtype is MessageType.CAMERA_CONTROL:
            name, value = request.get("name"), request.get("value")
            if name == "fov_rad" and isinstance(value, int | float):
                fov_rad = float(value)
                # A renderer can zoom; real optics cannot, and keep what was asked.
                if isinstance(source, FieldOfViewControl):
                    fov_rad = await loop.run_in_executor(run, source.set_fov_rad, fov_rad)
                return pack_json({"value": fov_rad})
            if not (isinstance(name, str) and isinstance(value, int)):
                raise FrameError(f"CAMERA_CONTROL needs a name and an integer value: {request}")
            granted = await loop.run_in_executor(run, source.set_control, name, value)
            return pack_json({"value": int(granted)})
        if mtype is MessageType.CAMERA_FRAME:
            kind = request.get("kind", "raw")
            quality = request.get("quality", 90)
            rotation = request.get("rotation", 180)
            if (
                kind not in ("raw", "jpeg", "png")
                or not (isinstance(quality, int) and 1 <= quality <= 100)
                or rotation not in (0, 90, 180, 270)
            ):
                raise CameraError(
                    f"frame kind {kind!r}, quality {quality!r}, rotation {rotation!r}: "
                    "raw|jpeg|png, 1..100, 0|90|180|270"
                )
            if session.camera is None:
                raise CameraError("the camera is not open: open it first")
            raw = await loop.run_in_executor(run, self._read_frame, source)
            if kind == "raw":
                return raw
            width, height, stride, name = session.camera
            return await loop.run_in_executor(
                run, self.frame_encoder, raw, width, height, stride, name, kind, quality, rotation
            )
        raise FrameError(f"{mtype.name} is not a request this server serves")

    @staticmethod
    def _read_frame(source: FrameSource) -> bytes:
        return bytes(source.read_frame())  # a copy: the source may reuse its buffer

    # -- the deadman -----------------------------------------------------------------------

    async def _watch(self) -> None:
        tick = min(0.05, self.deadline_s / 10)
        while True:
            await asyncio.sleep(tick)
            now = time.monotonic()
            session = self._controller
            if session is not None and session.busy == 0:
                silent_ms = (now - session.last_heard) * 1e3
                if silent_ms > self.deadline_s * 1e3:
                    self.stats.deadman_stops += 1
                    why = f"silent for {silent_ms:.0f} ms (deadline {self.deadline_s * 1e3:.0f} ms)"
                    await self._end_session(session, why, notify=True)
            for key, pending in list(self._pending.items()):
                if now - pending.created > self.handshake_timeout_s:
                    del self._pending[key]

    async def _end_session(
        self, session: _Session, reason: str, *, notify: bool = False, level: int = logging.WARNING
    ) -> None:
        """The client is gone: stop the motors, turn the LEDs off, release the robot."""
        if self._controller is not session:
            return
        self._controller = None
        self._expired[session.id] = reason
        while len(self._expired) > _MAX_EXPIRED:
            self._expired.popitem(last=False)
        if notify:
            message = f"session ended: {reason}; the robot was stopped"
            session.peer.send(
                encode_frame(MessageType.ERROR, 0, pack_error("LinkLostError", message), session.id)
            )
            session.peer.close()
        loop = asyncio.get_running_loop()
        try:
            await loop.run_in_executor(self._link_thread, self._stop_robot)
            log.log(level, "%s %s: motors stopped, LEDs off", session.peer.label, reason)
        except Exception as exc:
            log.error("%s %s, and stopping the robot failed: %s", session.peer.label, reason, exc)
        if session.camera is not None and self.frame_source is not None:
            session.camera = None
            with contextlib.suppress(Exception):
                await loop.run_in_executor(self._camera_thread, self.frame_source.close)

    def _stop_robot(self) -> None:
        """The confirmed stop batch, the same one a Robot sends (ego.safety.send_stop)."""
        send_stop(self.link)


class ServerThread:
    """A :class:`RemoteServer` on its own event loop in a background thread.

    For tests, benchmarks and a PC beside an emulator; ``ego serve`` runs the loop in
    the main thread instead.
    """

    def __init__(self, server: RemoteServer) -> None:
        self.server = server
        self._loop: asyncio.AbstractEventLoop | None = None
        self._thread: threading.Thread | None = None
        self._ready = threading.Event()
        self._error: BaseException | None = None
        self._stop: asyncio.Event | None = None

    @property
    def urls(self) -> list[str]:
        return self.server.urls

    @property
    def url(self) -> str:
        return self.server.urls[0]

    def start(self) -> ServerThread:
        self._thread = threading.Thread(target=self._run, name="ego-serve", daemon=True)
        self._thread.start()
        self._ready.wait()
        if self._error is not None:
            raise self._error
        return self

    def _run(self) -> None:
        asyncio.run(self._main())

    async def _main(self) -> None:
        self._loop = asyncio.get_running_loop()
        self._stop = asyncio.Event()
        try:
            await self.server.start()
        except BaseException as exc:
            self._error = exc
            self._ready.set()
            await self.server.aclose()
            return
        self._ready.set()
        await self._stop.wait()
        await self.server.aclose()

    def stop(self) -> None:
        """Stop the server (the robot is stopped if a client controls it); idempotent."""
        loop, stop, self._loop = self._loop, self._stop, None
        if loop is not None and stop is not None:
            with contextlib.suppress(RuntimeError):  # the loop already ended
                loop.call_soon_threadsafe(stop.set)
        if self._thread is not None:
            self._thread.join(timeout=10)
            self._thread = None

    def __enter__(self) -> ServerThread:
        return self.start()

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        self.stop()
