"""Hostile files for the tests: decompression bombs, FIFOs, huge worlds, deep nesting,
giant images; and a way to run a parse in a child process and measure it.

Each maker writes one file (or FIFO) into a folder and returns its path; :func:`make`
picks a maker by the file's name, which is what docs/bad_input.md's rows call
(``hostile("zstd-bomb.mcap")``). :func:`run_bounded` runs Python code in a child process
under a timeout and reports its exit, its output, its wall time and its peak resident
memory (from ``wait4``'s rusage of that child alone), so that a test can hold a parse to
a budget and a hang fails instead of hanging the suite.
"""

from __future__ import annotations

import json
import os
import signal
import struct
import subprocess
import sys
import tempfile
import time
import zlib
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from pathlib import Path

import lz4.frame
import zstandard
from mcap.data_stream import RecordBuilder
from mcap.records import Channel, Chunk, DataEnd, Footer, Header, Message, Metadata, Schema

__all__ = ["Bounded", "make", "run_bounded"]

MAGIC = b"\x89MCAP0\r\n"
#: A virtual memory cap on the child: a safety net so that the old code's bombs end
#: in MemoryError instead of taking the machine (far above any budget a test asserts).
CHILD_ADDRESS_SPACE = 6 << 30

# -- running a parse, measured -----------------------------------------------------------


@dataclass(frozen=True)
class Bounded:
    """How a child process ended: status (None if killed at the timeout), output, wall
    time, peak resident memory."""

    status: int | None
    stdout: str
    stderr: str
    wall_s: float
    peak_mb: float

    @property
    def lines(self) -> list[str]:
        return [line for line in self.stderr.splitlines() if line.strip()]


#: Runs ``argv[3:]`` as its child under the address-space cap ``argv[1]`` and writes the
#: child's peak RSS (kB, from wait4) to the descriptor ``argv[2]``. A child forked from
#: this small launcher starts small: one forked (or vforked) from the test process itself
#: would count that process's own 200 MB and more as its peak (Linux keeps the old mm's
#: high-water mark at exec).
_LAUNCHER = """
import os, resource, sys
pid = os.fork()
if pid == 0:
    cap = int(sys.argv[1])
    resource.setrlimit(resource.RLIMIT_AS, (cap, cap))
    os.execvp(sys.argv[3], sys.argv[3:])
_, status, usage = os.wait4(pid, 0)
os.write(int(sys.argv[2]), str(usage.ru_maxrss).encode())
sys.exit(os.waitstatus_to_exitcode(status) % 256)
"""


def run_bounded(args: list[str], timeout_s: float, cwd: Path | None = None) -> Bounded:
    """Run ``args`` (``[sys.executable, "-c", code]`` or a command), kill it at
    ``timeout_s``; its status, output, wall time and peak RSS (MB)."""
    read_peak, write_peak = os.pipe()
    with tempfile.TemporaryFile() as out, tempfile.TemporaryFile() as err:
        started = time.monotonic()
        proc = subprocess.Popen(
            [sys.executable, "-c", _LAUNCHER, str(CHILD_ADDRESS_SPACE), str(write_peak), *args],
            stdout=out, stderr=err, stdin=subprocess.DEVNULL, cwd=cwd,
            pass_fds=(write_peak,), start_new_session=True,
        )  # fmt: skip
        os.close(write_peak)
        status: int | None = None
        try:
            status = proc.wait(timeout=timeout_s)
            peak_kb = float(os.read(read_peak, 64) or b"0")
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)  # the launcher and the parse it runs
            proc.wait()
            peak_kb = 0.0  # killed: the budget is the timeout's
        finally:
            os.close(read_peak)
        wall_s = time.monotonic() - started
        out.seek(0)
        err.seek(0)
        return Bounded(status, out.read().decode(errors="replace"),
                       err.read().decode(errors="replace"), wall_s, peak_kb / 1024)  # fmt: skip


def python(code: str) -> list[str]:
    return [sys.executable, "-c", code]


# -- MCAP --------------------------------------------------------------------------------

EGO_METADATA = {"firmware": "webots", "version": "test", "robot": "{}", "world": "null"}
TOPICS = {1: ("/ego/sensors", "ego.Sensors"), 2: ("/ego/exchange", "ego.Exchange"),
          3: ("/camera/image", "foxglove.CompressedImage")}  # fmt: skip


def mcap_bytes(body: Iterable[object], metadata: dict[str, str] | None = None) -> bytes:
    """An MCAP file: header, ego's schemas and channels, the ego metadata, ``body``'s
    records (Messages, Chunks), data end, footer."""
    builder = RecordBuilder()
    records: list[object] = [Header(profile="", library="hostile")]
    for channel_id, (topic, schema) in TOPICS.items():
        records.append(Schema(id=channel_id, name=schema, encoding="jsonschema", data=b"{}"))
        records.append(Channel(id=channel_id, topic=topic, message_encoding="json",
                               metadata={}, schema_id=channel_id))  # fmt: skip
    records.append(Metadata(name="ego", metadata=metadata or EGO_METADATA))
    records += [*body, DataEnd(data_section_crc=0),
                Footer(summary_start=0, summary_offset_start=0, summary_crc=0)]  # fmt: skip
    for record in records:
        record.write(builder)  # type: ignore[attr-defined]
    return MAGIC + builder.end() + MAGIC


def message(channel_id: int, data: bytes, time_ns: int = 0) -> Message:
    return Message(channel_id=channel_id, sequence=0, log_time=time_ns,
                   publish_time=time_ns, data=data)  # fmt: skip


def _message_head(channel_id: int, size: int) -> bytes:
    """A Message record's opcode, length and fixed fields, for ``size`` bytes of data."""
    return struct.pack("<BQHIQQ", 0x05, 22 + size, channel_id, 0, 0, 0)


def _compressed_zeros(head: bytes, size: int, compress: Callable[[bytes], bytes]) -> bytes:
    piece = bytes(16 << 20)
    parts = [compress(head)]
    for _ in range(size // len(piece)):
        parts.append(compress(piece))
    parts.append(compress(bytes(size % len(piece))))
    return b"".join(parts)


def zstd_bomb(path: Path, size: int = 1 << 30, declared: int | None = None) -> Path:
    """One zstd chunk holding one camera message of ``size`` zero bytes (a 1 GiB one
    compresses to about 30 KB); the chunk declares its true size unless ``declared``."""
    head = _message_head(3, size)
    compressor = zstandard.ZstdCompressor(level=3).compressobj()
    data = _compressed_zeros(head, size, compressor.compress) + compressor.flush()
    true_size = len(head) + size
    chunk = Chunk(message_start_time=0, message_end_time=0,
                  uncompressed_size=true_size if declared is None else declared,
                  uncompressed_crc=0, compression="zstd", data=data)  # fmt: skip
    path.write_bytes(mcap_bytes([chunk]))
    return path


def lz4_bomb(path: Path, size: int = 565 << 20, declared: int = 1000) -> Path:
    """One lz4 chunk of ``size`` zero bytes (565 MB compress to about 2 MB) that declares
    only ``declared`` bytes."""
    head = _message_head(3, size)
    compressor = lz4.frame.LZ4FrameCompressor()
    data = compressor.begin() + _compressed_zeros(head, size, compressor.compress)
    data += compressor.flush()
    chunk = Chunk(message_start_time=0, message_end_time=0, uncompressed_size=declared,
                  uncompressed_crc=0, compression="lz4", data=data)  # fmt: skip
    path.write_bytes(mcap_bytes([chunk]))
    return path


def recording(path: Path, messages: list[tuple[int, object]],
              metadata: dict[str, str] | None = None) -> Path:  # fmt: skip
    """A plain (unchunked) recording of JSON messages (channel id, value)."""
    body = [message(cid, json.dumps(value).encode(), n * 1000) for n, (cid, value) in
            enumerate(messages)]  # fmt: skip
    path.write_bytes(mcap_bytes(body, metadata))
    return path


STEP = {"t": 0.032, "step": 1}
EXCHANGE = {"step": 1, "t": 0.032, "tx": "", "rx": ""}

# -- worlds ------------------------------------------------------------------------------

WBT_HEADER = "#VRML_SIM R2023b utf8\n"


def def_use_doubling(levels: int = 40) -> str:
    """A 2 KB world whose floor appearance reaches 2^(levels+1) nodes through DEF/USE."""
    lines = [WBT_HEADER, "DEF N0 Group { }"]
    lines += [f"DEF N{k} Group {{ children [ USE N{k - 1} USE N{k - 1} ] }}"
              for k in range(1, levels + 1)]  # fmt: skip
    lines.append(f"RectangleArena {{ floorAppearance PBRAppearance {{ baseColorMap USE "
                 f"N{levels} }} }}")  # fmt: skip
    return "\n".join(lines) + "\n"


def png(path: Path, width: int, height: int) -> Path:
    """A black greyscale PNG of any declared size, written without holding its pixels
    (12000x12000 is about 150 KB)."""
    compressor = zlib.compressobj(9)
    row = bytes(width + 1)  # filter byte 0, then the row
    idat = b"".join(compressor.compress(row) for _ in range(height)) + compressor.flush()

    def chunk(tag: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data))

    header = struct.pack(">IIBBBBB", width, height, 8, 0, 0, 0, 0)
    path.write_bytes(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", idat)
                     + chunk(b"IEND", b""))  # fmt: skip
    return path


def textured_world(path: Path, url: str) -> Path:
    path.write_text(WBT_HEADER + "RectangleArena { floorAppearance PBRAppearance { "
                    f'baseColorMap ImageTexture {{ url [ "{url}" ] }} }} }}\n')  # fmt: skip
    return path


def fifo(path: Path) -> Path:
    os.mkfifo(path)
    return path


def sparse(path: Path, size: int) -> Path:
    """A file of ``size`` zero bytes that takes no disk."""
    with open(path, "wb") as f:
        f.truncate(size)
    return path


def _write(text: str) -> Callable[[Path], Path]:
    def write(path: Path) -> Path:
        path.write_text(text)
        return path

    return write


_MAKERS: dict[str, Callable[[Path], Path]] = {
    "fifo.mcap": fifo,
    "fifo.conf": fifo,
    "fifo.toml": fifo,
    "huge.conf": lambda p: sparse(p, 300 << 20),
    "huge.toml": lambda p: sparse(p, 300 << 20),
    "zstd-bomb.mcap": zstd_bomb,
    "zstd-liar.mcap": lambda p: zstd_bomb(p, declared=1000),
    "lz4-liar.mcap": lz4_bomb,
    "big-message.mcap": lambda p: recording(p, [(3, {"data": "A" * (20 << 20)})]),
    "exchange-list.mcap": lambda p: recording(p, [(1, STEP), (2, [1, 2])]),
    "exchange-no-tx.mcap": lambda p: recording(p, [(1, STEP), (2, {"step": 1, "t": 0})]),
    "sensors-no-t.mcap": lambda p: recording(p, [(1, {"step": 1})]),
    "no-steps.mcap": lambda p: recording(p, []),
    "bogus-firmware.mcap": lambda p: recording(p, [(1, STEP), (2, EXCHANGE)],
                                               {**EGO_METADATA, "firmware": "bogus"}),
    "robot-not-json.mcap": lambda p: recording(p, [(1, STEP)],
                                               {**EGO_METADATA, "robot": "{"}),
    "many-boxes.toml": _write("[[box]]\nx_m = 0.1\n" * 100_000),
    "2000-boxes.toml": _write("[[box]]\n" * 2000),
    "deep.toml": _write("a = " + "[" * 2000 + "]" * 2000 + "\n"),
    "nan-track.toml": _write('[floor]\nkind = "track"\npoints = [[0, 0], [nan, 0.3]]\n'),
    "huge-track.toml": _write('[floor]\nkind = "track"\npoints = [[0, 0], [1e300, 0.3]]\n'),
    "many-boxes.wbt": _write(WBT_HEADER + "WoodenBox { }\n" * 100_000),
    "million-boxes.wbt": _write(WBT_HEADER + "WoodenBox { }\n" * 1_000_000),
    "deep.wbt": _write(WBT_HEADER + "Group { children [ " * 2000 + "] }" * 2000 + "\n"),
    "def-use.wbt": _write(def_use_doubling(40)),
    "unterminated.wbt": _write(WBT_HEADER + 'WorldInfo { title "' + "a" * (7 << 20) + "\n"),
    "many-tokens.wbt": _write(WBT_HEADER + "Shape { point [ " + "0 " * (3 << 20) + "] }\n"),
    "nan-box.wbt": _write(WBT_HEADER + "WoodenBox { size nan 0.1 0.1 }\n"),
    "inf-arena.wbt": _write(WBT_HEADER + "RectangleArena { floorSize inf 1 }\n"),
    "huge-box.wbt": _write(WBT_HEADER + "WoodenBox { translation 1e300 0 0 }\n"),
    "huge-camera.wbt": _write(WBT_HEADER + "E-puck { camera_width 100000 }\n"),
    "fifo-texture.wbt": lambda p: (fifo(p.parent / "fifo.png"), textured_world(p, "fifo.png"))[1],
    "huge-texture.wbt": lambda p: (png(p.parent / "huge.png", 12000, 12000),
                                   textured_world(p, "huge.png"))[1],
}


def _outside_texture(path: Path) -> Path:
    """A world in a folder of its own whose texture is a real PNG one folder up."""
    inside = path.parent / "inside"
    inside.mkdir(exist_ok=True)
    png(path.parent / "outside.png", 8, 8)
    return textured_world(inside / path.name, "../outside.png")


_MAKERS["outside-texture.wbt"] = _outside_texture


def make(folder: Path, name: str) -> str:
    """The hostile file ``name`` (one of :data:`_MAKERS`), made once in ``folder``."""
    path = folder / name
    if name == "outside-texture.wbt":
        made = folder / "inside" / name
        return str(made if made.exists() else _MAKERS[name](path))
    if not os.path.lexists(path):
        _MAKERS[name](path)
    return str(path)


def names() -> list[str]:
    return sorted(_MAKERS)
