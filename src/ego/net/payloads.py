"""The payloads ego serve's frames carry: JSON, errors, ASCII commands, and the PART and
FETCH of a reply split across datagrams (no I/O)."""

from __future__ import annotations

import json
import struct
from collections.abc import Mapping
from typing import Any

from ego.errors import FrameError
from ego.net.frames import MAX_PAYLOAD, SEALED_OVERHEAD, MessageType

__all__ = [
    "ASCII_REPLY_LINES",
    "FETCH",
    "PART",
    "error_fields",
    "pack_ascii",
    "pack_error",
    "pack_fetch",
    "pack_json",
    "pack_part",
    "split_reply",
    "unpack_ascii",
    "unpack_error",
    "unpack_fetch",
    "unpack_json",
    "unpack_part",
]


def pack_json(obj: Mapping[str, Any]) -> bytes:
    return json.dumps(obj, separators=(",", ":")).encode()


def unpack_json(payload: bytes) -> dict[str, Any]:
    """A JSON object, or FrameError."""
    try:
        obj = json.loads(payload.decode())
    except (UnicodeDecodeError, ValueError) as exc:
        raise FrameError(f"payload is not JSON: {exc}") from exc
    if not isinstance(obj, dict):
        raise FrameError(f"payload is JSON {type(obj).__name__}, expected an object")
    return obj


def pack_error(name: str, message: str, fields: Mapping[str, object] | None = None) -> bytes:
    """An ERROR payload: the ego error class to raise on the client, its message, and the
    attributes the error carries beyond it (``holder_pid``, ``path``...), as JSON."""
    return pack_json({"error": name, "message": message, "fields": dict(fields or {})})


def error_fields(exc: BaseException) -> dict[str, object]:
    """The JSON-able attributes an error carries beyond its message, for pack_error."""
    return {
        key: value
        for key, value in vars(exc).items()
        if not key.startswith("_") and isinstance(value, (str, int, float, bool, type(None)))
    }


def unpack_error(payload: bytes) -> tuple[str, str, dict[str, object]]:
    try:
        obj = unpack_json(payload)
        name, message = obj["error"], obj["message"]
        fields = obj.get("fields", {})
    except (FrameError, KeyError, AttributeError):
        return "RemoteError", f"malformed error reply {payload[:80]!r}", {}
    return str(name), str(message), fields if isinstance(fields, dict) else {}


#: ASCII commands relayed to the dsPIC, and how many reply lines each has (docs/protocol.md:
#: V answers two lines, K two, S and C one). R (reset) is not relayed: its banner would
#: leave the server's link to reset itself.
ASCII_REPLY_LINES: Mapping[str, int] = {"V": 2, "C": 1, "S": 1, "K": 2}
_ASCII = struct.Struct("<cB")


def pack_ascii(letter: str, lines: int) -> bytes:
    return _ASCII.pack(letter.encode("ascii"), lines)


def unpack_ascii(payload: bytes) -> tuple[str, int]:
    """The letter and line count of an ASCII request; FrameError if not relayable."""
    if len(payload) != _ASCII.size:
        raise FrameError(f"ASCII request of {len(payload)} bytes, expected {_ASCII.size}")
    raw, lines = _ASCII.unpack(payload)
    letter = raw.decode("latin-1")
    if ASCII_REPLY_LINES.get(letter) != lines:
        relayed = ", ".join(f"{k} ({n} lines)" for k, n in ASCII_REPLY_LINES.items())
        raise FrameError(f"ASCII command {letter!r} with {lines} lines is not relayed: {relayed}")
    return letter, lines


#: A PART payload starts with the reply's type, its total size and this slice's offset.
PART = struct.Struct("<BxxxII")
#: A FETCH payload: the sequence number of the big reply and the offset wanted.
FETCH = struct.Struct("<II")


def pack_part(type_: MessageType, total: int, offset: int, data: bytes) -> bytes:
    return PART.pack(type_, total, offset) + data


def unpack_part(payload: bytes) -> tuple[MessageType, int, int, bytes]:
    """The reply type, total size, offset and data of a PART; FrameError if inconsistent."""
    if len(payload) < PART.size:
        raise FrameError(f"PART of {len(payload)} bytes lacks its {PART.size}-byte header")
    type_, total, offset = PART.unpack_from(payload)
    data = payload[PART.size :]
    if type_ not in (MessageType.OK, MessageType.ERROR):
        raise FrameError(f"PART of a type {type_} reply")
    if total > MAX_PAYLOAD or offset + len(data) > total or (not data and offset < total):
        raise FrameError(f"PART slice {offset}+{len(data)} of {total} bytes is inconsistent")
    return MessageType(type_), total, offset, data


def pack_fetch(seq: int, offset: int) -> bytes:
    return FETCH.pack(seq, offset)


def unpack_fetch(payload: bytes) -> tuple[int, int]:
    if len(payload) != FETCH.size:
        raise FrameError(f"FETCH of {len(payload)} bytes, expected {FETCH.size}")
    seq, offset = FETCH.unpack(payload)
    return int(seq), int(offset)


def split_reply(type_: MessageType, payload: bytes, offset: int, chunk_size: int) -> bytes:
    """The PART payload carrying ``payload[offset:]`` that fits a ``chunk_size`` datagram."""
    room = chunk_size - SEALED_OVERHEAD - PART.size
    if room <= 0:
        raise ValueError(f"chunk size {chunk_size} leaves no room for data")
    if not 0 <= offset < len(payload):
        raise FrameError(f"offset {offset} is outside the {len(payload)}-byte reply")
    return pack_part(type_, len(payload), offset, payload[offset : offset + room])
