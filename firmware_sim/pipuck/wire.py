"""The framed protocol between ``i2c_shim.c`` and the emulator, sans-I/O.

Both ways a frame is a little-endian u32 length and that many bytes. A request starts
with an op byte; a reply starts with an i32 result, >= 0 or -errno (the layouts are in
i2c_shim.c's header). :class:`Session` is one shim connection, which is one open
``/dev/i2c-N``: it is fed bytes and returns the reply bytes to send.
"""

from __future__ import annotations

import errno
import struct
import threading

from firmware_sim.pipuck.bus import Message
from firmware_sim.pipuck.i2cdev import I2cDev, OpenFile

__all__ = ["MAX_FRAME", "Session"]

MAX_FRAME = 1 << 20
_I32 = struct.Struct("<i")
_MSG = struct.Struct("<HHH")


class ProtocolError(Exception):
    """The peer sent a frame that is not a request: the connection is dropped."""


class Session:
    """One shim connection: frames in, replies out. ``lock`` is the bus lock that every
    operation on the emulated robot holds (one transaction at a time, as on the wire)."""

    def __init__(self, dev: I2cDev, lock: threading.Lock | threading.RLock) -> None:
        self._dev = dev
        self._lock = lock
        self._buffer = bytearray()
        self.file: OpenFile | None = None

    def feed(self, data: bytes) -> bytes:
        """Take received bytes; return every complete request's reply, framed."""
        self._buffer += data
        out = bytearray()
        while len(self._buffer) >= 4:
            (length,) = struct.unpack_from("<I", self._buffer)
            if length == 0 or length > MAX_FRAME:
                raise ProtocolError(f"frame of {length} bytes")
            if len(self._buffer) < 4 + length:
                break
            request = bytes(self._buffer[4 : 4 + length])
            del self._buffer[: 4 + length]
            with self._lock:
                reply = self.handle(request)
            out += struct.pack("<I", len(reply)) + reply
        return bytes(out)

    def handle(self, request: bytes) -> bytes:
        op, body = request[:1], request[1:]
        try:
            if op == b"O":
                return self._open(body)
            if op == b"E":
                (bus,) = struct.unpack("<I", body)
                return _I32.pack(self._dev.node_state(bus))
            if self.file is None:
                return _I32.pack(-errno.EBADF)
            return self._dispatch(op, body, self.file)
        except (struct.error, IndexError) as exc:
            raise ProtocolError(f"malformed {op!r} request") from exc

    def _open(self, body: bytes) -> bytes:
        if self.file is not None:
            raise ProtocolError("a second open on one connection")
        bus, flags = struct.unpack("<Ii", body)
        result = self._dev.open(bus, flags)
        if isinstance(result, int):
            return _I32.pack(result)
        self.file = result
        return _I32.pack(0)

    def _dispatch(self, op: bytes, body: bytes, file: OpenFile) -> bytes:
        if op == b"I":
            cmd, arg = struct.unpack("<IQ", body)
            return _I32.pack(self._dev.ioctl(file, cmd, arg))
        if op == b"F":
            return struct.pack("<iQ", 0, self._dev.funcs(file))
        if op == b"R":
            return self._rdwr(body, file)
        if op == b"S":
            read_write, command, size, has_data, n = struct.unpack_from("<BBIBB", body)
            data = body[8 : 8 + n] if has_data else None
            res, back = self._dev.smbus(file, read_write, command, size, data)
            return _I32.pack(res) + bytes([len(back)]) + back
        if op == b"r":
            (count,) = struct.unpack("<I", body)
            res, data = self._dev.read(file, count)
            return _I32.pack(res) + data
        if op == b"w":
            return _I32.pack(self._dev.write(file, body))
        raise ProtocolError(f"unknown op {op!r}")

    def _rdwr(self, body: bytes, file: OpenFile) -> bytes:
        (nmsgs,) = struct.unpack_from("<I", body)
        msgs = []
        at = 4
        while at < len(body):
            addr, flags, length = _MSG.unpack_from(body, at)
            data = body[at + 6 : at + 6 + length]
            if len(data) != length:
                raise ProtocolError("truncated I2C_RDWR message")
            msgs.append(Message(addr, flags, length, data))
            at += 6 + length
        if nmsgs <= 42 and len(msgs) != nmsgs:
            raise ProtocolError("I2C_RDWR message count")
        res, replies = self._dev.rdwr(file, nmsgs, msgs)
        return _I32.pack(res) + b"".join(replies)
