"""The seam's batch: one step's requests, their bytes and how to read the reply (no I/O).

A channel carries a :class:`Batch` and returns its reply bytes; the codec that builds one
from requests and a firmware profile is :func:`ego.serial.protocol.encode_batch`.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

from ego.errors import ExtraBytesError, ShortReplyError
from ego.seam.profile import Command, WireFormat

__all__ = ["Batch", "Request"]


@dataclass(frozen=True, slots=True)
class Request:
    """One command of a batch with its arguments (speeds, an LED and its value...)."""

    command: Command
    arguments: tuple[int, ...] = ()


@dataclass(frozen=True, slots=True)
class Batch:
    """The bytes of one time step and how to read their answer.

    ``reply_size`` counts every byte the dsPIC sends back for this batch, ``U``'s
    600-byte prefixes included; 0 means the dsPIC stays silent and nobody may wait.
    """

    requests: tuple[Request, ...]
    tx: bytes
    reply_size: int
    _formats: tuple[WireFormat, ...]
    #: For each request, the command on the wire whose reply holds its values and how
    #: to take them out (None: as they are); empty when every request went as itself.
    _routes: tuple[tuple[int, Callable[[Sequence[float]], tuple[float, ...]] | None], ...] = ()
    _wire: tuple[Request, ...] = ()  # the wire's requests where routing changed them

    @property
    def wire(self) -> tuple[Request, ...]:
        """The requests ``tx`` holds: what a channel answering requests answers (WiFi)."""
        return self._wire or self.requests

    @property
    def expects_reply(self) -> bool:
        return self.reply_size > 0

    def decode(self, reply: bytes | bytearray | memoryview) -> list[tuple[float, ...]]:
        """Values for each request, in request order (``()`` for actuators).

        Raises ShortReplyError / ExtraBytesError when ``reply`` is not exactly
        ``reply_size`` bytes: the length is the protocol's only integrity check.
        """
        view = memoryview(reply).cast("B")
        if len(view) < self.reply_size:
            raise ShortReplyError(
                f"reply of {len(view)} bytes, the batch asks for {self.reply_size}"
            )
        if len(view) > self.reply_size:
            raise ExtraBytesError(
                f"reply of {len(view)} bytes, the batch asks for {self.reply_size}"
            )
        # docs/protocol.md: U's 600 bytes arrive before the rest of the batch's replies.
        offset = 0
        prefixes: list[tuple[float, ...]] = []
        for fmt in self._formats:
            prefixes.append(fmt.prefix.unpack_from(view, offset))
            offset += fmt.prefix.size
        values: list[tuple[float, ...]] = []
        for fmt, prefix in zip(self._formats, prefixes, strict=True):
            values.append(prefix + fmt.reply.unpack_from(view, offset))
            if fmt.check is not None:
                fmt.check(view[offset : offset + fmt.reply.size])
            offset += fmt.reply.size
        if not self._routes:
            return values
        return [values[i] if take is None else take(values[i]) for i, take in self._routes]

    def with_values(self, reply: bytes, index: int, values: Sequence[int]) -> bytes:
        """``reply`` (checked as :meth:`decode` checks it) with request ``index``'s values
        replaced by ``values``, packed as its wire format packs them: what a server that
        holds the robot for its client answers (ego.servers.dashboard.served).

        Raises ValueError for a request whose values are taken out of another's reply
        or checked on the wire (the e-puck2's sensor packet): they cannot be rewritten
        alone.
        """
        self.decode(reply)
        wire, take = self._routes[index] if self._routes else (index, None)
        fmt = self._formats[wire]
        if take is not None or fmt.check is not None:
            raise ValueError(f"request {index}'s values cannot be rewritten in its reply")
        offset = sum(f.prefix.size for f in self._formats)
        offset += sum(f.reply.size for f in self._formats[:wire])
        out = bytearray(reply)
        fmt.reply.pack_into(out, offset, *values)
        return bytes(out)
