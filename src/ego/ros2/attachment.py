"""The attachment rmw_zenoh puts on every sample: sequence number, source time, GID.

A publisher sends ``AttachmentData(sequence_number_++, source_timestamp, gid)`` (jazzy
``src/detail/rmw_publisher_data.cpp:309-312``; the sequence starts at 1, :204) serialized
with zenoh-ext's ``Serializer``: an int64, an int64, then the GID array
(``src/detail/attachment_helpers.cpp:67-74``; read back in the same order, :77-82).
zenoh-ext writes numbers as fixed-size little-endian and an array as a sequence: its
length as LEB128, then the elements (eclipse-zenoh/roadmap rfcs/ALL/Serialization.md,
"Numbers" and "Sequences"). With the 16-byte GID of every distribution in
:mod:`ego.ros2.distros` that is 33 bytes::

    <int64 LE sequence number><int64 LE source timestamp, ns since the epoch>10<16 GID bytes>

A subscription drops every sample without an attachment (jazzy
``src/detail/rmw_subscription_data.cpp:221-228``), so the attachment is not optional.

Usage::

    data = encode_attachment(Attachment(1, time.time_ns(), gid), "jazzy")
    decode_attachment(data, "jazzy").sequence_number    # 1
"""

from __future__ import annotations

import struct
from typing import NamedTuple

from ego.errors import FrameError, OutOfRangeError
from ego.ros2.distros import Distro, distro_format

__all__ = ["Attachment", "attachment_size", "decode_attachment", "encode_attachment"]

_INT64 = struct.Struct("<q")
_INT64_MIN, _INT64_MAX = -(2**63), 2**63 - 1


class Attachment(NamedTuple):
    """What rides with each sample: ``sequence_number`` (int64, from 1 per publisher),
    ``source_timestamp_ns`` (int64, ns since the Unix epoch) and ``gid`` (the publisher's
    GID bytes)."""

    sequence_number: int
    source_timestamp_ns: int
    gid: bytes


def _leb128(value: int) -> bytes:
    out = bytearray()
    while True:
        byte = value & 0x7F
        value >>= 7
        if value:
            out.append(byte | 0x80)
        else:
            out.append(byte)
            return bytes(out)


def attachment_size(distro: Distro | str) -> int:
    """How many bytes an attachment has in ``distro`` (33 with a 16-byte GID)."""
    gid_size = distro_format(distro).gid_size
    return 2 * _INT64.size + len(_leb128(gid_size)) + gid_size


def encode_attachment(attachment: Attachment, distro: Distro | str) -> bytes:
    """The attachment bytes of ``attachment`` as ``distro``'s rmw_zenoh writes them."""
    gid_size = distro_format(distro).gid_size
    seq, stamp, gid = attachment
    for name, value in (("sequence number", seq), ("source timestamp", stamp)):
        if isinstance(value, bool) or not isinstance(value, int):
            raise TypeError(f"attachment {name} must be an int, not {type(value).__name__}")
        if not _INT64_MIN <= value <= _INT64_MAX:
            raise OutOfRangeError(f"attachment {name} {value} does not fit an int64")
    gid = bytes(gid)
    if len(gid) != gid_size:
        raise OutOfRangeError(f"GID of {len(gid)} bytes: {Distro(distro).value} wants {gid_size}")
    return _INT64.pack(seq) + _INT64.pack(stamp) + _leb128(gid_size) + gid


def decode_attachment(data: bytes | bytearray | memoryview, distro: Distro | str) -> Attachment:
    """The :class:`Attachment` in ``data``; :class:`~ego.errors.FrameError` unless ``data``
    is exactly one attachment of ``distro``."""
    gid_size = distro_format(distro).gid_size
    raw = bytes(data)
    want = attachment_size(distro)
    if len(raw) != want:
        raise FrameError(f"attachment of {len(raw)} bytes: {Distro(distro).value} sends {want}")
    prefix = _leb128(gid_size)
    at = 2 * _INT64.size
    if raw[at : at + len(prefix)] != prefix:
        raise FrameError(
            f"attachment GID length prefix {raw[at : at + len(prefix)].hex()} is not "
            f"{prefix.hex()} ({gid_size} bytes)"
        )
    (seq,) = _INT64.unpack_from(raw, 0)
    (stamp,) = _INT64.unpack_from(raw, _INT64.size)
    return Attachment(seq, stamp, raw[at + len(prefix) :])
