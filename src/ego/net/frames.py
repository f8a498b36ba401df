"""ego's remote protocol on the wire: the frame, its header and its seal (no I/O).

Every message, over TCP or UDP, is one frame::

    offset  size  field
    0       2     magic  b"EG"
    2       1     protocol version (PROTOCOL_VERSION)
    3       1     message type (MessageType), with bit 0x80 set when the frame is sealed
    4       4     session id, u32 little-endian (0 before the handshake)
    8       4     sequence number, u32 (1, 2, ... per session; 0 = unsolicited)
    12      4     payload length, u32 (at most MAX_PAYLOAD)
    16      n     payload
    16+n    4|16  CRC32 of bytes 0 .. 16+n, or, sealed, the frame's MAC

Once a handshake with a shared secret is done, every frame of the session is *sealed*:
its trailer is the first 16 bytes of HMAC-SHA256, under the session key
(:func:`ego.net.handshake.session_key`), of a direction byte (``C`` client to server,
``S`` server to client) and bytes 0 .. 16+n. The MAC covers the type, session, sequence
number and payload, so nothing can be injected, rewritten or reflected back; the
sequence numbers (:class:`SequenceGuard`) make a replayed frame stale. Without a secret
(loopback only) the trailer is a CRC32, which catches corruption and nothing else.

The header layout is frozen across protocol versions, so that a peer speaking another
version is told so in a frame it can still read. The client is stop-and-wait: it sends
request ``n+1`` only once request ``n`` was answered (the server refuses one that comes
while another runs), so over UDP a lost request or reply is retransmitted with the
*same* sequence number, and the server's :class:`SequenceGuard` answers a duplicate
from its cache instead of running the batch twice. A reply is matched to its request
by session and sequence number alone: a late, duplicated or reordered datagram can never
be taken for another step's reply.

A reply too big for one datagram (a camera frame over UDP) comes as a first
:data:`MessageType.PART`; the client fetches the rest with :data:`MessageType.FETCH`
requests, each an ordinary sequenced request.
"""

from __future__ import annotations

import enum
import hashlib
import hmac
import struct
import zlib
from dataclasses import dataclass

from ego.errors import FrameError, VersionMismatchError

__all__ = [
    "DEFAULT_CHUNK_SIZE",
    "HEADER",
    "MAC_SIZE",
    "MAGIC",
    "MAX_DATAGRAM",
    "MAX_PAYLOAD",
    "MAX_PREAUTH_PAYLOAD",
    "OVERHEAD",
    "PROTOCOL_VERSION",
    "REQUEST_TYPES",
    "RESPONSE_TYPES",
    "SEALED",
    "SEALED_OVERHEAD",
    "Frame",
    "FrameKey",
    "FrameReader",
    "MessageType",
    "decode_frame",
    "encode_frame",
    "peek_session",
]

MAGIC = b"EG"
PROTOCOL_VERSION = 2
#: magic, version, type, session, sequence number, payload length.
HEADER = struct.Struct("<2sBBIII")
_CRC = struct.Struct("<I")
#: Bytes of a sealed frame's MAC (HMAC-SHA256 truncated to 128 bits, as in TLS and IPsec).
MAC_SIZE = 16
#: Bit of the type byte that marks a sealed frame.
SEALED = 0x80
#: Bytes a frame adds to its payload (an unsealed one; a sealed one adds SEALED_OVERHEAD).
OVERHEAD = HEADER.size + _CRC.size
SEALED_OVERHEAD = HEADER.size + MAC_SIZE
#: Largest payload accepted: 1 MiB holds a 640x480 RGB888 camera frame (921,600 bytes).
MAX_PAYLOAD = 1 << 20
#: Largest payload of a frame from a peer that has not authenticated: a HELLO or an
#: AUTH is a few hundred bytes, so a stranger never makes the server buffer more.
MAX_PREAUTH_PAYLOAD = 1024
#: Largest UDP payload over IPv4.
MAX_DATAGRAM = 65507
#: Datagram size the server splits big replies into (camera frames over UDP).
DEFAULT_CHUNK_SIZE = 16 * 1024


class MessageType(enum.IntEnum):
    """What a frame carries. Requests go client to server, responses come back."""

    HELLO = 1  # JSON {client, nonce[, cookie]}; OK: JSON {nonce, auth, proof...} or COOKIE
    AUTH = 2  # JSON {proof}; OK (sealed): JSON {firmware, ...}
    STEP = 3  # messages.pack_step(requests); OK: exactly the batch's reply bytes
    ASCII = 4  # pack_ascii(letter, lines); OK: the reply lines, each ending \r\n
    PING = 5  # heartbeat; OK: empty
    BYE = 6  # goodbye; OK: empty
    CAMERA_OPEN = 7  # JSON {width, height, pixel_format}; OK: JSON {width, height, stride}
    CAMERA_FRAME = 8  # JSON {kind: raw|jpeg|png, quality}; OK: the frame's bytes
    CAMERA_CONTROL = 9  # JSON {name, value}; OK: JSON {value}
    CAMERA_CLOSE = 10  # OK: empty
    FETCH = 11  # pack_fetch(seq, offset); answered by a PART
    INFO = 12  # OK: JSON of the firmware the server's link talks to (after a restart)
    OK = 64
    ERROR = 65  # pack_error(class name, message)
    PART = 66  # pack_part(type, total, offset, data): a slice of a big reply
    WORKING = 67  # the request is still running: wait, do not give up
    COOKIE = 68  # JSON {cookie}: say HELLO again with it (UDP: proves the address)


REQUEST_TYPES = frozenset(t for t in MessageType if t < MessageType.OK)
RESPONSE_TYPES = frozenset(t for t in MessageType if t >= MessageType.OK)


@dataclass(frozen=True, slots=True)
class Frame:
    """One decoded message."""

    type: MessageType
    seq: int
    payload: bytes = b""
    session: int = 0


class FrameKey:
    """A session key and the directions it seals and opens frames in.

    The client seals with direction ``C`` and opens ``S``; the server the reverse, so a
    frame cannot be reflected back to its sender.
    """

    __slots__ = ("_started", "opens", "seals")

    def __init__(self, key: bytes, *, server: bool) -> None:
        self.seals, self.opens = (b"S", b"C") if server else (b"C", b"S")
        # HMAC(key, direction + frame), each started once and copied per frame: the key
        # is not set up again for every frame (a burst of thousands stays cheap).
        self._started = {d: hmac.new(key, d, hashlib.sha256) for d in (b"C", b"S")}

    def mac(self, direction: bytes, data: bytes | memoryview) -> bytes:
        digest = self._started[direction].copy()
        digest.update(data)
        return digest.digest()[:MAC_SIZE]

    def __repr__(self) -> str:
        return f"<FrameKey seals {self.seals!r}>"  # never the key


def encode_frame(
    type_: MessageType,
    seq: int,
    payload: bytes = b"",
    session: int = 0,
    key: FrameKey | None = None,
) -> bytes:
    """The bytes of one frame, sealed with ``key`` if given; ValueError for a payload over
    :data:`MAX_PAYLOAD`."""
    if len(payload) > MAX_PAYLOAD:
        raise ValueError(f"payload of {len(payload)} bytes exceeds the {MAX_PAYLOAD}-byte limit")
    code = type_ | SEALED if key is not None else type_
    head = HEADER.pack(MAGIC, PROTOCOL_VERSION, code, session, seq, len(payload))
    if key is not None:
        return b"".join((head, payload, key.mac(key.seals, head + payload)))
    crc = zlib.crc32(payload, zlib.crc32(head))
    return b"".join((head, payload, _CRC.pack(crc)))


def _check_header(
    data: bytes | bytearray | memoryview, max_payload: int = MAX_PAYLOAD
) -> tuple[int, int, int, int, int]:
    magic, version, type_, session, seq, length = HEADER.unpack_from(data)
    if magic != MAGIC:
        raise FrameError(f"not an ego frame: magic {bytes(magic)!r}, expected {MAGIC!r}")
    if length > max_payload:
        raise FrameError(f"frame of {length} payload bytes exceeds the {max_payload}-byte limit")
    return version, type_, session, seq, length


def _frame_size(type_: int, length: int) -> int:
    return (SEALED_OVERHEAD if type_ & SEALED else OVERHEAD) + length


def peek_session(data: bytes | bytearray | memoryview) -> int | None:
    """The session id in a datagram's header (to find its key), or None if too short."""
    if len(data) < HEADER.size:
        return None
    return int(HEADER.unpack_from(data)[3])


def decode_frame(
    data: bytes | bytearray | memoryview,
    key: FrameKey | None = None,
    max_payload: int = MAX_PAYLOAD,
) -> Frame:
    """Exactly one frame (a datagram, or a frame cut out of a stream).

    With ``key``, the frame must be sealed by the other side with it; without, it must
    not be sealed. Raises FrameError for anything else: too short, wrong magic,
    oversized, a length that disagrees with the data, a bad CRC or MAC, an unsealed
    frame where a sealed one is due, an unknown type; and its subclass
    VersionMismatchError for an intact frame of another protocol version.
    """
    view = memoryview(data).cast("B")
    if len(view) < OVERHEAD:
        raise FrameError(f"frame of {len(view)} bytes is shorter than the {OVERHEAD}-byte minimum")
    version, type_, session, seq, length = _check_header(view, max_payload)
    if len(view) != _frame_size(type_, length):
        raise FrameError(
            f"frame of {len(view)} bytes, its header announces {_frame_size(type_, length)}"
        )
    end = HEADER.size + length
    if type_ & SEALED:
        if key is None:
            raise FrameError("a sealed frame outside an authenticated session")
        if not hmac.compare_digest(key.mac(key.opens, view[:end]), view[end:]):
            raise FrameError("frame MAC mismatch: forged, altered or from another session")
    else:
        (crc,) = _CRC.unpack_from(view, end)
        if zlib.crc32(view[:end]) != crc:
            raise FrameError("frame CRC mismatch: corrupted in transit")
        if key is not None:
            raise FrameError("an unsealed frame in an authenticated session")
    if version != PROTOCOL_VERSION:
        raise VersionMismatchError(
            f"peer speaks ego remote protocol version {version}, this side speaks "
            f"{PROTOCOL_VERSION}: install the same ego version on both ends",
            version,
            seq,
            session,
        )
    try:
        mtype = MessageType(type_ & ~SEALED)
    except ValueError:
        raise FrameError(f"unknown message type {type_}") from None
    return Frame(mtype, seq, bytes(view[HEADER.size : end]), session)


class FrameReader:
    """Frames cut out of a byte stream (TCP), fed in pieces of any size.

    A bad header leaves no way to find the next frame, so after the first FrameError the
    reader stays broken and raises it again: the connection must be closed. ``key``
    (set once the handshake is done) is the key every later frame must be sealed with;
    ``max_payload`` bounds what a peer may make the reader buffer (small until it has
    authenticated).
    """

    def __init__(self, max_payload: int = MAX_PAYLOAD) -> None:
        self._buf = bytearray()
        self._error: FrameError | None = None
        self.key: FrameKey | None = None
        self.max_payload = max_payload

    def feed(self, data: bytes) -> list[Frame]:
        """The frames completed by ``data``, in order (raises FrameError as above)."""
        if self._error is not None:
            raise self._error
        self._buf += data
        frames: list[Frame] = []
        buf, start = self._buf, 0
        try:
            while len(buf) - start >= HEADER.size:
                # Checked before the payload arrives: an oversized length is refused
                # without buffering it.
                view = memoryview(buf)[start:]
                try:
                    _, type_, _, _, length = _check_header(view, self.max_payload)
                finally:
                    view.release()
                total = _frame_size(type_, length)
                if len(buf) - start < total:
                    break
                chunk = bytes(buf[start : start + total])
                start += total
                frames.append(decode_frame(chunk, self.key, self.max_payload))
        except FrameError as exc:
            self._error = exc
            self._buf.clear()
            raise
        # Cut once, not after every frame: a burst of thousands stays linear.
        del buf[:start]
        return frames

    @property
    def buffered(self) -> int:
        """Bytes of an incomplete frame held back."""
        return len(self._buf)
