"""An MCAP file's records read with bounds: no chunk or message can make ego exhaust
the machine.

The mcap library's readers decompress a chunk whole, trusting its sizes (a 19 KB zstd
file became 1 GB). Here the file is walked with its :class:`~mcap.stream_reader.
StreamReader` told to hand chunks over still compressed; each chunk's declared size is
checked against :data:`MAX_CHUNK_BYTES` and against what the file as a whole may expand
to (:data:`EXPANSION` times its size) before anything is decompressed, and the
decompression itself stops one byte past the declared size, so that a chunk that lies
about its size costs no more than one that tells the truth. A message over
:data:`MAX_MESSAGE_BYTES` is refused. The bounds are in docs/bad_input.md.
"""

from __future__ import annotations

import io
import struct
import zlib
from dataclasses import dataclass, field
from typing import IO, Any, cast

import lz4.frame  # type: ignore[import-untyped]  # no stubs; a dependency of mcap
import zstandard
from mcap.data_stream import ReadDataStream
from mcap.exceptions import McapError
from mcap.records import Channel, Chunk, Message, Metadata, Schema
from mcap.stream_reader import StreamReader

from ego.errors import RecordingError
from ego.seam.files import BoundedReader, describe_bytes

__all__ = ["EXPANSION", "MAX_CHUNK_BYTES", "MAX_MESSAGE_BYTES", "RawMessage", "read_records"]

#: A chunk's uncompressed size, at most (ego writes chunks of 1 MiB).
MAX_CHUNK_BYTES = 64 << 20
#: One message's data, at most (a 640x480 JPEG frame, base64 in JSON, is under 1 MiB).
MAX_MESSAGE_BYTES = 16 << 20
#: All chunks together decompress to at most this many times the file's size (or
#: MAX_CHUNK_BYTES, if more): ego's recordings expand about 5 times.
EXPANSION = 64
#: A message record's fixed part: channel id, sequence, log time, publish time.
_MESSAGE_HEAD = 2 + 4 + 8 + 8
_OPCODE_SCHEMA, _OPCODE_CHANNEL, _OPCODE_MESSAGE = 0x03, 0x04, 0x05


@dataclass(frozen=True, slots=True)
class RawMessage:
    topic: str
    log_time: int
    data: bytes


@dataclass
class RawRecording:
    """What an MCAP file holds: metadata by name, each topic's schema name, the messages
    in log-time order."""

    metadata: dict[str, dict[str, str]] = field(default_factory=dict)
    schemas: dict[str, str] = field(default_factory=dict)
    messages: list[RawMessage] = field(default_factory=list)


def read_records(file: BoundedReader, file_size: int) -> RawRecording:
    """Every record of ``file`` (an open MCAP file of ``file_size`` bytes), within the
    bounds; RecordingError naming the file otherwise."""
    loader = _Loader(file.name, max(MAX_CHUNK_BYTES, EXPANSION * file_size))
    try:
        stream = cast(IO[bytes], file)  # it reads with read(n), all a StreamReader calls
        reader = StreamReader(stream, emit_chunks=True, record_size_limit=MAX_CHUNK_BYTES + 4096)
        for record in reader.records:
            loader.take(record)
    except RecordingError:
        raise
    except (McapError, ValueError, KeyError, struct.error, EOFError) as exc:
        what = type(exc).__name__ if not str(exc) else str(exc)
        if type(exc).__name__ == "EndOfFile":
            what = "the file ends before its footer (cut short?)"
        raise RecordingError(f"{file.name}: not a readable ego recording: {what}") from exc
    loader.raw.messages.sort(key=lambda m: m.log_time)
    return loader.raw


class _Loader:
    def __init__(self, name: str, budget: int) -> None:
        self.name = name
        self.budget = budget  # bytes all chunks may still decompress to
        self.raw = RawRecording()
        self.schema_names: dict[int, str] = {}
        self.topics: dict[int, str] = {}

    def refuse(self, reason: str) -> RecordingError:
        return RecordingError(f"{self.name}: {reason}")

    def take(self, record: Any) -> None:
        if isinstance(record, Schema):
            self.schema_names[record.id] = record.name
        elif isinstance(record, Channel):
            if record.schema_id and record.schema_id not in self.schema_names:
                raise self.refuse(f"channel {record.topic} names schema {record.schema_id}, "
                                  "which the file does not define before it")  # fmt: skip
            self.topics[record.id] = record.topic
            self.raw.schemas[record.topic] = self.schema_names.get(record.schema_id, "")
        elif isinstance(record, Message):
            self.message(record.channel_id, record.log_time, record.data)
        elif isinstance(record, Chunk):
            for inner in self.chunk_records(record):
                self.take(inner)
        elif isinstance(record, Metadata):
            self.raw.metadata[record.name] = dict(record.metadata)

    def message(self, channel_id: int, log_time: int, data: bytes) -> None:
        topic = self.topics.get(channel_id)
        if topic is None:
            raise self.refuse(f"a message on channel {channel_id}, which the file does not "
                              "define before it")  # fmt: skip
        if len(data) > MAX_MESSAGE_BYTES:
            bound = describe_bytes(MAX_MESSAGE_BYTES)
            raise self.refuse(f"a message of {len(data)} bytes on {topic} is over the {bound} "
                              "bound for a message")  # fmt: skip
        self.raw.messages.append(RawMessage(topic, log_time, data))

    def chunk_records(self, chunk: Chunk) -> list[Any]:
        data = self.inflate(chunk)
        stream = ReadDataStream(io.BytesIO(data))
        records: list[Any] = []
        while stream.count < len(data):
            opcode, length = stream.read1(), stream.read8()
            start = stream.count
            if length > len(data) - start:
                raise self.refuse(f"a record of {length} bytes runs past the end of its chunk")
            if opcode == _OPCODE_MESSAGE:
                if length < _MESSAGE_HEAD:
                    raise self.refuse(f"a message record of {length} bytes is too short")
                records.append(Message.read(stream, length))
            elif opcode == _OPCODE_CHANNEL:
                records.append(Channel.read(stream))
            elif opcode == _OPCODE_SCHEMA:
                records.append(Schema.read(stream))
            padding = length - (stream.count - start)
            if padding < 0:
                raise self.refuse("a record in a chunk is longer than its declared length")
            stream.read(padding)
        return records

    def inflate(self, chunk: Chunk) -> bytes:
        """The chunk's records, decompressed within the bounds."""
        declared = chunk.uncompressed_size
        if declared > MAX_CHUNK_BYTES:
            raise self.refuse(f"a chunk declares {declared} bytes uncompressed, over the "
                              f"{describe_bytes(MAX_CHUNK_BYTES)} bound for a chunk")  # fmt: skip
        if declared > self.budget:
            raise self.refuse(f"its chunks expand to more than {EXPANSION} times the file's "
                              "size: refused as a decompression bomb")  # fmt: skip
        self.budget -= declared
        data = _decompress(chunk.compression, chunk.data, declared, self.name)
        if len(data) != declared:
            holds = "more" if len(data) > declared else f"only {len(data)}"
            raise self.refuse(f"a {chunk.compression or 'plain'} chunk declares {declared} "
                              f"bytes uncompressed but holds {holds}")  # fmt: skip
        if chunk.uncompressed_crc and zlib.crc32(data) != chunk.uncompressed_crc:
            raise self.refuse("a chunk fails its CRC check")
        return data


def _decompress(compression: str, data: bytes, declared: int, name: str) -> bytes:
    """At most ``declared + 1`` bytes of ``data`` decompressed: one more than declared
    tells a chunk that lies about its size, at no more cost than an honest one."""
    limit = declared + 1
    try:
        if compression == "":
            return data[:limit]
        if compression == "zstd":
            out = bytearray()
            with zstandard.ZstdDecompressor().stream_reader(data) as reader:
                while len(out) < limit and (piece := reader.read(min(1 << 20, limit - len(out)))):
                    out += piece
            return bytes(out)
        if compression == "lz4":
            piece = lz4.frame.LZ4FrameDecompressor().decompress(data, max_length=limit)
            return bytes(piece)
    except (zstandard.ZstdError, RuntimeError) as exc:  # lz4's is a RuntimeError
        raise RecordingError(f"{name}: a {compression} chunk cannot be decompressed: "
                             f"{exc}") from exc  # fmt: skip
    raise RecordingError(f"{name}: a chunk compressed with {compression!r}, which is not "
                         "zstd, lz4 or none")  # fmt: skip
