"""The PC side: a remote robot as a :class:`~ego.serial.transport.Transport`, and its camera.

:class:`RemoteTransport` turns the byte-level calls of a :class:`~ego.serial.link.Link`
into framed requests to ``ego serve``, so that ``ego.Robot("tcp://robot:4242")`` works
with no special case in the robot:

* ``write`` of a binary batch sends a STEP request and waits for its reply; ``read``
  then serves the reply's bytes. Errors the server met on the robot's link come back
  as the same ego error class (LinkTimeoutError, RobotResetError...), raised by ``write``;
* ``write(b"V\\n")`` (an ASCII command) is relayed as an ASCII request, its reply lines
  served by ``read_line``;
* the resynchronisation zeros the link sends after a fault are not forwarded: the
  server's own link has resynchronised the serial line before answering;
* while the controller waits out a step (:meth:`waiting_until`, which ``Robot.step``
  calls), a heartbeat thread pings the server when the line is quiet, so that a
  controller with a 1 s step is not taken for a dead one; once the controller stops
  stepping (it hangs, or loops without calling step), the pings stop too and the
  server's deadman stops the robot after ``deadline_s``. Before the first step nothing
  drives the robot, and the pings go on. ``close`` says goodbye.

Over UDP each request is retransmitted with the same sequence number, a bounded number
of times, until its reply comes; replies to anything else are discarded.

>>> link = Link(RemoteTransport.from_url("udp://127.0.0.1:4242"))   # doctest: +SKIP
"""

from __future__ import annotations

import contextlib
import logging
import math
import socket
import threading
import time
import weakref
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import ego.errors
from ego import __version__
from ego.errors import (
    AuthenticationError,
    CameraCaptureError,
    CameraError,
    EgoError,
    FrameError,
    ImageFormatError,
    LinkLostError,
    LinkTimeoutError,
    OutOfRangeError,
    PortNotFoundError,
    ProtocolError,
    RemoteError,
    RobotBusyError,
)
from ego.remote.auth import (
    NONCE_SIZE,
    check_proof,
    client_proof,
    coerce_secret,
    new_nonce,
    secret_from_environment,
    server_proof,
)
from ego.remote.wire import (
    ASCII_REPLY_LINES,
    MAX_DATAGRAM,
    Frame,
    FrameReader,
    MessageType,
    decode_frame,
    encode_frame,
    next_seq,
    pack_ascii,
    pack_fetch,
    pack_json,
    parse_url,
    unpack_error,
    unpack_json,
    unpack_part,
)
from ego.serial.transport import Transport

if TYPE_CHECKING:
    from ego.camera.source import GrantedFormat, PixelFormat

__all__ = ["RemoteFrameSource", "RemoteStats", "RemoteTransport", "error_from_reply"]

log = logging.getLogger(__name__)

_ERROR_CLASSES: dict[str, type[EgoError]] = {
    name: cls
    for name, cls in vars(ego.errors).items()
    if isinstance(cls, type) and issubclass(cls, EgoError)
}


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
    #: Datagrams or frames that failed to decode (CRC...), discarded.
    corrupt: int = 0
    heartbeats: int = 0
    bytes_sent: int = 0
    bytes_received: int = 0


def _is_resync(data: bytes) -> bool:
    """The link's resynchronisation bytes: zeros first (a batch or an ASCII line never is)."""
    return data[0] == 0


class RemoteTransport(Transport):
    """A robot behind ``ego serve``, reached over TCP or UDP.

    ``secret`` defaults to ``EGO_SECRET_FILE`` / ``EGO_SECRET`` from the environment.
    ``timeout_s`` bounds one request (the server may retry the serial line meanwhile);
    over UDP a request unanswered after ``retransmit_s`` (doubling, at most a quarter of
    the server's deadline) is
    sent again, at most ``retries`` times. Connecting happens at construction.
    """

    baudrate = None
    #: The server's own link resynchronises the serial line: ours is never relayed.
    relays_resync = False

    def __init__(
        self,
        host: str,
        port: int,
        *,
        protocol: str = "tcp",
        secret: str | bytes | None = None,
        timeout_s: float = 5.0,
        connect_timeout_s: float = 2.0,
        retransmit_s: float = 0.02,
        retries: int = 8,
        heartbeat: bool = True,
    ) -> None:
        if protocol not in ("tcp", "udp"):
            raise ValueError(f"protocol {protocol!r} is not tcp or udp")
        self.host, self.port, self.protocol = host, port, protocol
        shown = f"[{host}]" if ":" in host else host
        self.name = f"{protocol}://{shown}:{port}"
        self.secret = coerce_secret(secret) if secret is not None else secret_from_environment()
        self.timeout_s = timeout_s
        self.connect_timeout_s = connect_timeout_s
        self.retransmit_s = retransmit_s
        self.retries = retries
        self.heartbeat = heartbeat
        self.stats = RemoteStats()
        #: What the server said of itself and its robot at the handshake.
        self.server_info: dict[str, Any] = {}
        self._sock: socket.socket | None = None
        self._reader = FrameReader()
        self._session = 0
        self._seq = 0
        self._rx = bytearray()
        self._lock = threading.Lock()
        self._last_activity = 0.0
        #: Until when the heartbeat may keep the session alive (time.monotonic()): no
        #: limit until the controller's first step, then the end of each step's wait.
        self._alive_until = math.inf
        self._beat_stop = threading.Event()
        self._beat_thread: threading.Thread | None = None
        self._open()

    @classmethod
    def from_url(
        cls, url: str, secret: str | bytes | None = None, **options: Any
    ) -> RemoteTransport:
        """``tcp://host:port`` or ``udp://host:port`` (port 4242 if omitted)."""
        try:
            scheme, host, port = parse_url(url)
        except ValueError as exc:
            raise PortNotFoundError(str(exc)) from exc
        return cls(host, port, protocol=scheme, secret=secret, **options)

    # -- connection and handshake ----------------------------------------------------------

    def _open(self) -> None:
        kind = socket.SOCK_STREAM if self.protocol == "tcp" else socket.SOCK_DGRAM
        try:
            infos = socket.getaddrinfo(self.host, self.port, type=kind)
            family, _, _, _, addr = infos[0]
            sock = socket.socket(family, kind)
        except OSError as exc:
            raise PortNotFoundError(f"cannot reach {self.name}: {exc}") from exc
        try:
            sock.settimeout(self.connect_timeout_s)
            sock.connect(addr)  # for UDP: only the server's datagrams are received
            if kind == socket.SOCK_STREAM:
                sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        except OSError as exc:
            sock.close()
            raise PortNotFoundError(f"no ego server at {self.name}: {exc}") from exc
        self._sock = sock
        self._reader = FrameReader()
        self._session = 0
        self._seq = 0
        self._rx.clear()
        try:
            self._handshake()
        except BaseException:
            self._sock = None
            sock.close()
            raise
        if self.heartbeat:
            self._beat_stop = threading.Event()
            self._beat_thread = threading.Thread(
                target=_heartbeat,
                args=(weakref.ref(self), self._beat_stop, max(0.01, self.deadline_s / 4)),
                name="ego-remote-heartbeat",
                daemon=True,
            )
            self._beat_thread.start()

    def _handshake(self) -> None:
        nonce = new_nonce()
        try:
            hello = self._call(
                MessageType.HELLO,
                pack_json({"client": f"ego {__version__}", "nonce": nonce.hex()}),
                timeout_s=self.connect_timeout_s,
            )
        except LinkTimeoutError as exc:
            why = str(exc).removeprefix(f"{self.name}: ")
            raise PortNotFoundError(f"no ego server answers at {self.name}: {why}") from exc
        except LinkLostError as exc:
            why = str(exc).removeprefix(f"{self.name}: ")
            raise PortNotFoundError(f"no ego server at {self.name}: {why}") from exc
        try:
            challenge = unpack_json(hello)
            server_nonce = bytes.fromhex(str(challenge["nonce"]))
            auth = bool(challenge["auth"])
        except (KeyError, ValueError) as exc:
            raise FrameError(f"{self.name}: malformed handshake reply: {exc}") from exc
        if len(server_nonce) != NONCE_SIZE:
            raise FrameError(f"{self.name}: server nonce of {len(server_nonce)} bytes")
        if auth and self.secret is None:
            raise AuthenticationError(
                f"{self.name} requires a shared secret: pass secret=..., or set "
                "EGO_SECRET_FILE or EGO_SECRET"
            )
        proof = (
            client_proof(self.secret, server_nonce, nonce, self._session) if self.secret else b""
        )
        welcome = unpack_json(
            self._call(
                MessageType.AUTH,
                pack_json({"proof": proof.hex()}),
                timeout_s=self.connect_timeout_s,
            )
        )
        if auth:
            assert self.secret is not None
            expected = server_proof(self.secret, nonce, server_nonce, self._session)
            try:
                theirs = bytes.fromhex(str(welcome.get("proof", "")))
            except ValueError:
                theirs = b""
            if not check_proof(expected, theirs):
                raise AuthenticationError(
                    f"{self.name} could not prove it knows the shared secret: not our robot?"
                )
        self.server_info = welcome
        log.info("%s: connected, %s firmware", self.name, welcome.get("firmware", "?"))

    @property
    def firmware(self) -> str | None:
        """The firmware the server's link talks to ("webots", "gctronic")."""
        value = self.server_info.get("firmware")
        return str(value) if value is not None else None

    @property
    def deadline_s(self) -> float:
        """How long the server lets this client be silent before it stops the robot."""
        return float(self.server_info.get("deadline_s", 0.5))

    # -- requests --------------------------------------------------------------------------

    def call(
        self, mtype: MessageType, payload: bytes = b"", *, timeout_s: float | None = None
    ) -> bytes:
        """One request; its OK payload, or the ego error the server replied with."""
        with self._lock:
            return self._call(mtype, payload, timeout_s=timeout_s)

    def _call(
        self, mtype: MessageType, payload: bytes = b"", *, timeout_s: float | None = None
    ) -> bytes:
        if self._sock is None:
            raise LinkLostError(f"{self.name}: not connected")
        timeout = self.timeout_s if timeout_s is None else timeout_s
        deadline = time.monotonic() + timeout
        reply = self._roundtrip(mtype, payload, deadline)
        if reply.type is MessageType.PART:
            reply = self._fetch_rest(reply, deadline)
        if reply.type is MessageType.ERROR:
            raise error_from_reply(reply.payload, self.name)
        if reply.type is not MessageType.OK:
            raise FrameError(f"{self.name}: unexpected {reply.type.name} reply to {mtype.name}")
        return reply.payload

    def _fetch_rest(self, first: Frame, deadline: float) -> Frame:
        """A reply that came in slices (UDP): FETCH the rest, one slice per request."""
        kind, total, offset, data = unpack_part(first.payload)
        if offset != 0:
            raise FrameError(f"{self.name}: a big reply starts at offset {offset}")
        buf = bytearray(data)
        while len(buf) < total:
            part = self._roundtrip(MessageType.FETCH, pack_fetch(first.seq, len(buf)), deadline)
            if part.type is MessageType.ERROR:
                raise error_from_reply(part.payload, self.name)
            if part.type is not MessageType.PART:
                raise FrameError(f"{self.name}: {part.type.name} reply to FETCH")
            kind2, total2, offset2, data2 = unpack_part(part.payload)
            if (kind2, total2, offset2) != (kind, total, len(buf)):
                raise FrameError(f"{self.name}: slice {offset2} of {total2}, expected {len(buf)}")
            buf += data2
        return Frame(kind, first.seq, bytes(buf), first.session)

    def _roundtrip(self, mtype: MessageType, payload: bytes, deadline: float) -> Frame:
        """Send one request and return the reply with its sequence number."""
        self._seq = seq = next_seq(self._seq)
        data = encode_frame(mtype, seq, payload, self._session)
        self.stats.requests += 1
        self._last_activity = time.monotonic()
        try:
            if self.protocol == "tcp":
                self._send(data)
                reply = self._receive(seq, deadline)
                if reply is None:
                    raise LinkTimeoutError(
                        f"{self.name}: no reply to {mtype.name} within {self._age(deadline)}"
                    )
            else:
                reply = self._roundtrip_udp(mtype, data, seq, deadline)
        finally:
            self._last_activity = time.monotonic()
        if mtype is MessageType.HELLO:
            self._session = reply.session
        return reply

    def _roundtrip_udp(self, mtype: MessageType, data: bytes, seq: int, deadline: float) -> Frame:
        wait = self.retransmit_s
        attempts = 0
        self._send(data)
        while True:
            reply = self._receive(seq, min(deadline, time.monotonic() + wait))
            if reply is not None and reply.type is not MessageType.WORKING:
                return reply
            if time.monotonic() >= deadline:
                raise LinkTimeoutError(
                    f"{self.name}: no reply to {mtype.name} {seq} within {self._age(deadline)} "
                    f"({attempts} retransmissions)"
                )
            if reply is not None:
                # WORKING: the server has the request and is running it (the serial line
                # may be retrying): keep waiting, up to the request timeout.
                attempts = 0
                wait = self.retransmit_s
                continue
            if attempts >= self.retries:
                raise LinkTimeoutError(
                    f"{self.name}: no reply to {mtype.name} {seq} after {attempts} retransmissions"
                )
            attempts += 1
            self.stats.retransmits += 1
            self._send(data)
            # Backing off, but never quieter than the heartbeat: the server would take a
            # silence beyond its deadline for a dead client.
            wait = min(wait * 2, self.deadline_s / 4)

    def _age(self, deadline: float) -> str:
        return f"{(self.timeout_s + time.monotonic() - deadline):.2f} s"

    def _send(self, data: bytes) -> None:
        assert self._sock is not None
        try:
            self._sock.sendall(data)
        except OSError as exc:
            raise LinkLostError(f"{self.name}: send failed: {exc}") from exc
        self.stats.bytes_sent += len(data)

    def _receive(self, seq: int, until: float) -> Frame | None:
        """The reply to ``seq`` before ``until``, or None; other frames are discarded."""
        sock = self._sock
        assert sock is not None
        while True:
            remaining = until - time.monotonic()
            if remaining <= 0:
                return None
            sock.settimeout(remaining)
            try:
                chunk = sock.recv(MAX_DATAGRAM if self.protocol == "udp" else 1 << 16)
            except TimeoutError:
                return None
            except OSError as exc:  # ECONNREFUSED (UDP: nobody listens), ECONNRESET...
                raise LinkLostError(f"{self.name}: {exc}") from exc
            if not chunk and self.protocol == "tcp":
                raise LinkLostError(f"{self.name}: the server closed the connection")
            self.stats.bytes_received += len(chunk)
            try:
                frames = (
                    self._reader.feed(chunk) if self.protocol == "tcp" else [decode_frame(chunk)]
                )
            except FrameError as exc:
                if self.protocol == "tcp":  # a stream cannot recover from a bad frame
                    raise LinkLostError(f"{self.name}: corrupt stream: {exc}") from exc
                self.stats.corrupt += 1
                log.debug("%s: dropped a corrupt datagram: %s", self.name, exc)
                continue
            for frame in frames:
                if frame.seq == 0 and frame.type is MessageType.ERROR:
                    # Unsolicited: the server ended the session (deadman, shutdown).
                    raise error_from_reply(frame.payload, self.name)
                if frame.seq == seq and (self._session in (0, frame.session)):
                    return frame
                self.stats.stale += 1

    # -- the Transport interface -----------------------------------------------------------

    def write(self, data: bytes) -> None:
        """Relay one batch or ASCII command and wait for its reply (served by ``read``).

        Raises the ego error the server met (LinkTimeoutError, RobotResetError...), or
        LinkTimeoutError / LinkLostError for the network itself.
        """
        data = bytes(data)
        if not data or _is_resync(data):
            return  # the server's link resynchronised its line before replying
        self._rx.clear()
        if data[0] < 0x80:
            text = data.decode("ascii", "replace").strip()
            lines = ASCII_REPLY_LINES.get(text)
            if lines is None:
                raise ProtocolError(
                    f"{self.name}: ASCII command {text!r} is not relayed "
                    f"(relayed: {', '.join(ASCII_REPLY_LINES)})"
                )
            reply = self.call(MessageType.ASCII, pack_ascii(text, lines))
        else:
            reply = self.call(MessageType.STEP, data)
        self._rx += reply

    def read(self, size: int, timeout_s: float) -> bytes:
        """Bytes of the last reply; b'' at once when it is used up (nothing else comes)."""
        out = bytes(self._rx[:size])
        del self._rx[:size]
        return out

    def pending(self) -> bytes:
        out = bytes(self._rx)
        self._rx.clear()
        return out

    def read_exactly(self, size: int, timeout_s: float) -> bytes:
        if len(self._rx) < size:
            partial = self.pending()
            err = LinkTimeoutError(
                f"{self.name}: {len(partial)} of {size} reply bytes (the server sent no more)"
            )
            err.partial = partial  # type: ignore[attr-defined]
            raise err
        return self.read(size, timeout_s)

    def read_line(self, timeout_s: float) -> bytes:
        end = self._rx.find(b"\n")
        return self.read(end + 1 if end >= 0 else len(self._rx), timeout_s)

    def drain(self, quiet_s: float, max_s: float) -> bytes:
        return self.pending()

    def reopen(self) -> None:
        """Connect again (a new session: the robot was stopped meanwhile).

        A server still holding our old session refuses with RobotBusyError until its
        deadman releases it; that counts as "not back yet" (LinkLostError), so the link
        keeps trying until its reconnect deadline.
        """
        self._shutdown(goodbye=True)
        try:
            self._open()
        except RobotBusyError as exc:
            raise LinkLostError(str(exc)) from exc
        log.info("%s: reconnected", self.name)

    def close(self) -> None:
        """Say goodbye (the server stops the robot) and close the socket; idempotent."""
        self._shutdown(goodbye=True)

    def _shutdown(self, goodbye: bool) -> None:
        self._beat_stop.set()
        thread, self._beat_thread = self._beat_thread, None
        if thread is not None and thread is not threading.current_thread():
            thread.join(timeout=5)
        with self._lock:
            sock = self._sock
            if sock is None:
                return
            if goodbye and self._session:
                with contextlib.suppress(EgoError, OSError):
                    self._call(MessageType.BYE, timeout_s=0.3)
            self._sock = None
            self._session = 0
            sock.close()

    @property
    def is_open(self) -> bool:
        return self._sock is not None

    # -- heartbeat -------------------------------------------------------------------------

    def waiting_until(self, deadline_s: float) -> None:
        self._alive_until = deadline_s

    def _beat(self) -> None:
        """Ping the server if nothing was sent for a while (called by the heartbeat thread)."""
        now = time.monotonic()
        if now - self._last_activity < self.deadline_s / 4 or now > self._alive_until:
            return
        if not self._lock.acquire(blocking=False):
            return  # a request is under way: that is activity enough
        try:
            if self._sock is not None and not self._beat_stop.is_set():
                self.stats.heartbeats += 1
                self._call(MessageType.PING, timeout_s=self.deadline_s)
        except (EgoError, OSError) as exc:
            log.debug("%s: heartbeat failed: %s", self.name, exc)
        finally:
            self._lock.release()

    # -- camera ----------------------------------------------------------------------------

    def frame_source(self) -> RemoteFrameSource:
        """The robot's camera, fetched through this connection."""
        return RemoteFrameSource(self)


def _heartbeat(
    ref: weakref.ReferenceType[RemoteTransport], stop: threading.Event, interval_s: float
) -> None:
    """The heartbeat thread. It holds the transport weakly: a transport dropped without
    ``close`` stops beating, and the server's deadman then stops the robot."""
    while not stop.wait(interval_s / 4):
        transport = ref()
        if transport is None:
            return
        transport._beat()
        del transport


class RemoteFrameSource:
    """The camera of a robot behind ``ego serve``: a frame source for ego's Camera.

    Raw frames come in the pixel format asked at :meth:`open` (RGB565, so the client's
    Camera converts and rotates them locally); :meth:`fetch_encoded` asks the server for
    a JPEG or PNG instead, far smaller on a slow network.

    >>> camera = Camera(source=RemoteFrameSource(robot.link.transport))   # doctest: +SKIP
    """

    def __init__(self, transport: Transport) -> None:
        if not isinstance(transport, RemoteTransport):
            raise CameraError(f"{transport.name} is not a remote robot: no remote camera there")
        self.transport = transport
        self.granted: GrantedFormat | None = None

    def _request(self, mtype: MessageType, payload: bytes = b"") -> bytes:
        try:
            return self.transport.call(mtype, payload)
        except (LinkTimeoutError, LinkLostError) as exc:
            raise CameraCaptureError(f"camera of {self.transport.name}: {exc}") from exc

    def open(self, width: int, height: int, pixel_format: PixelFormat | str) -> GrantedFormat:
        """Start capture near ``width`` x ``height``; what the robot's camera granted."""
        from ego.camera.source import GrantedFormat, PixelFormat

        fmt = PixelFormat(pixel_format)
        request = {"width": width, "height": height, "pixel_format": fmt.value}
        reply = unpack_json(self._request(MessageType.CAMERA_OPEN, pack_json(request)))
        self.granted = GrantedFormat(
            int(reply["width"]), int(reply["height"]), int(reply["stride"])
        )
        return self.granted

    def read_frame(self) -> bytes:
        """The next raw frame, ``stride_bytes`` x ``height`` bytes."""
        return self._request(MessageType.CAMERA_FRAME, pack_json({"kind": "raw"}))

    def fetch_encoded(self, kind: str = "jpeg", quality: int = 90, rotation: int = 180) -> bytes:
        """The next frame as a JPEG (``quality`` 1..100) or PNG file's bytes, converted
        and rotated (degrees counter-clockwise; 180 undoes the camera's mounting) on the
        robot."""
        from ego.camera.convert import ROTATIONS
        from ego.camera.encode import check_quality

        if kind not in ("jpeg", "png"):
            raise ImageFormatError(f"image kind {kind!r} is not jpeg or png")
        quality = check_quality(quality)
        if isinstance(rotation, bool) or rotation not in ROTATIONS:
            raise OutOfRangeError(f"rotation {rotation!r} is not one of 0, 90, 180, 270 degrees")
        request = {"kind": kind, "quality": quality, "rotation": rotation}
        return self._request(MessageType.CAMERA_FRAME, pack_json(request))

    def set_control(self, name: str, value: int) -> int:
        """Set a camera control (brightness, contrast...); the value the camera took."""
        request = {"name": name, "value": int(value)}
        reply = unpack_json(self._request(MessageType.CAMERA_CONTROL, pack_json(request)))
        return int(reply["value"])

    def set_fov_rad(self, fov_rad: float) -> float:
        """Zoom an emulated camera; a real one keeps its optics and reports ``fov_rad``."""
        request = {"name": "fov_rad", "value": float(fov_rad)}
        reply = unpack_json(self._request(MessageType.CAMERA_CONTROL, pack_json(request)))
        return float(reply["value"])

    def close(self) -> None:
        """Stop capture; harmless when not open or when the connection is gone."""
        if self.granted is None:
            return
        self.granted = None
        with contextlib.suppress(EgoError):
            self._request(MessageType.CAMERA_CLOSE)
