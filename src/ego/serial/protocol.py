"""The batch codec: a step's requests in, bytes out, and bytes back to a batch (no I/O).

Nothing here does I/O, so every quirk of docs/protocol.md is tested on bytes alone:

* a batch ends with 0x00, and only then does the dsPIC answer, all replies back to
  back in command order, with no header, length or checksum;
* a batch of actuator commands only (``D``, ``L``, ``P``) gets no reply at all;
* ``U`` sends its 600 sample bytes at once when parsed, before the batch's replies,
  and adds one byte (the newest sample's index) to them;
* where a profile has an "all sensors" packet (the e-puck2), reads ride in it when that
  costs less.

Each firmware's formats come from its :class:`~ego.seam.profile.Profile`
(:data:`ego.serial.profiles.PROFILES`).
"""

from __future__ import annotations

import struct
from collections.abc import Callable, Iterable, Sequence

from ego.errors import UnsupportedDeviceError
from ego.seam.batch import Batch, Request
from ego.seam.profile import Command, Profile, WireFormat

__all__ = ["encode_batch", "parse_batch", "reply_sizes"]


def encode_batch(requests: Iterable[Request], profile: Profile) -> Batch:
    """The bytes of one step: every request's command and arguments, then 0x00.

    An empty batch encodes to nothing at all (a lone 0x00 would be harmless, but
    sending nothing costs nothing).
    """
    reqs = tuple(requests)
    if not reqs:
        return Batch((), b"", 0, ())
    wire, routes = _through_packet(reqs, profile)
    tx = bytearray()
    formats: list[WireFormat] = []
    for req in wire:
        fmt = profile.wire_format(req.command)
        tx.append(req.command.value)
        try:
            tx += fmt.arguments.pack(*req.arguments)
        except struct.error as exc:
            raise ValueError(
                f"command {req.command.letter!r} takes arguments {fmt.arguments.format!r}, "
                f"got {req.arguments!r}"
            ) from exc
        formats.append(fmt)
    tx.append(Command.END.value)
    reply = sum(f.prefix.size + f.reply.size for f in formats)
    return Batch(reqs, bytes(tx), reply, tuple(formats), routes, tuple(wire) if routes else ())


_Routes = tuple[tuple[int, Callable[[Sequence[float]], tuple[float, ...]] | None], ...]


def _through_packet(reqs: tuple[Request, ...], profile: Profile) -> tuple[list[Request], _Routes]:
    """The requests as they go on the wire: where the profile has an "all sensors"
    packet (the e-puck2), the reads it holds ride in one ``ALL_SENSORS`` when that costs
    less than asking them one by one (:meth:`Profile.cost_s`), or when the packet is
    asked anyway (a family only it serves); every ``ALL_SENSORS`` is asked once.

    The e-puck2 profile's docstring says why and what was measured.
    """
    cover = profile.all_sensors
    covered = [r for r in reqs if r.command in cover and not r.arguments]
    asked = any(r.command is Command.ALL_SENSORS for r in reqs)
    if not asked and (
        not covered
        or sum(profile.cost_s(r.command) for r in covered) <= profile.cost_s(Command.ALL_SENSORS)
    ):
        return list(reqs), ()
    wire: list[Request] = []
    routes: list[tuple[int, Callable[[Sequence[float]], tuple[float, ...]] | None]] = []
    packet: int | None = None
    for req in reqs:
        take = cover.get(req.command) if not req.arguments else None
        if take is not None or req.command is Command.ALL_SENSORS:
            if packet is None:
                packet = len(wire)
                wire.append(Request(Command.ALL_SENSORS))
            routes.append((packet, take))
        else:
            routes.append((len(wire), None))
            wire.append(req)
    return wire, tuple(routes)


def parse_batch(tx: bytes, profile: Profile) -> Batch:
    """The batch that ``tx`` encodes, read back as the dsPIC would (a relay's view).

    For tools that watch a line (a logger, a relay between a PC and a robot) and must
    know how many reply bytes a batch asks for; ``ego serve`` needs none, as it is sent
    requests, not bytes (ego.net.messages). Raises ValueError for bytes that are not
    exactly one well-formed batch: an unknown or unsupported command, arguments cut
    short, or anything after the final 0x00.
    """
    data = memoryview(tx)
    requests: list[Request] = []
    pos = 0
    while True:
        if pos >= len(data):
            raise ValueError("batch does not end with 0x00")
        byte = data[pos]
        pos += 1
        if byte == Command.END:
            break
        try:
            command = Command(byte)
            fmt = profile.wire_format(command)
        except (ValueError, UnsupportedDeviceError) as exc:
            raise ValueError(
                f"byte 0x{byte:02x} at {pos - 1} is not a command of {profile.firmware}"
            ) from exc
        end = pos + fmt.arguments.size
        if end > len(data):
            raise ValueError(f"command {command.letter!r} at {pos - 1} lacks its arguments")
        requests.append(
            Request(command, tuple(int(v) for v in fmt.arguments.unpack(data[pos:end])))
        )
        pos = end
    if pos != len(data):
        raise ValueError(f"{len(data) - pos} bytes after the end of the batch")
    if not requests:
        raise ValueError("a batch needs at least one command")
    return encode_batch(requests, profile)


def reply_sizes(profile: Profile, commands: Sequence[Command]) -> list[int]:
    """Reply bytes of each command under ``profile`` (for overhead tables)."""
    formats = [profile.wire_format(c) for c in commands]
    return [f.prefix.size + f.reply.size for f in formats]
