"""What a client asks of ``ego serve``, as typed requests: packed, and checked once when read.

A request frame's payload becomes one of the dataclasses below through
:func:`parse_request`, which is the only place the server checks what a client sent:
a STEP is a list of protocol requests (the server encodes the batch for its own link,
so it never parses bytes meant for the dsPIC), the camera requests are JSON objects
whose fields are checked by type and range. Anything else is a FrameError naming what
was wrong.
"""

from __future__ import annotations

import math
import struct
from dataclasses import dataclass
from typing import Any

from ego.errors import FrameError
from ego.net.frames import Frame, MessageType
from ego.net.payloads import (
    pack_ascii,
    pack_fetch,
    pack_json,
    unpack_ascii,
    unpack_fetch,
    unpack_json,
)
from ego.seam.batch import Request
from ego.seam.profile import Command
from ego.seam.validate import ROTATIONS

__all__ = [
    "Ascii",
    "Bye",
    "CameraClose",
    "CameraControl",
    "CameraFrame",
    "CameraOpen",
    "Fetch",
    "Info",
    "Ping",
    "RobotCall",
    "Step",
    "pack_request",
    "pack_step",
    "parse_request",
    "unpack_step",
]

#: A STEP request is its command byte, how many arguments follow, and each as an i32.
#: The commands a STEP may carry (END only ends a batch on the serial line).
_COMMANDS = {c.value: c for c in Command if c is not Command.END}
#: More requests than any batch of a step holds (every command, with every LED twice).
MAX_STEP_REQUESTS = 64
IMAGE_KINDS = ("raw", "jpeg", "png")


@dataclass(frozen=True, slots=True)
class Step:
    requests: tuple[Request, ...]


@dataclass(frozen=True, slots=True)
class Ascii:
    letter: str
    lines: int


@dataclass(frozen=True, slots=True)
class Ping:
    pass


@dataclass(frozen=True, slots=True)
class Bye:
    pass


@dataclass(frozen=True, slots=True)
class Info:
    pass


@dataclass(frozen=True, slots=True)
class Fetch:
    seq: int
    offset: int


@dataclass(frozen=True, slots=True)
class CameraOpen:
    width: int
    height: int
    pixel_format: str


@dataclass(frozen=True, slots=True)
class CameraFrame:
    kind: str = "raw"
    quality: int = 90
    rotation: int = 180


@dataclass(frozen=True, slots=True)
class CameraControl:
    name: str
    value: int | float


@dataclass(frozen=True, slots=True)
class CameraClose:
    pass


#: What the server runs on the robot's link or camera (everything but Fetch).
RobotCall = (
    Step | Ascii | Ping | Bye | Info | CameraOpen | CameraFrame | CameraControl | CameraClose
)


def pack_step(requests: tuple[Request, ...] | list[Request]) -> bytes:
    """A STEP payload: each request's command byte, argument count and i32 arguments."""
    fmt = ["<"]
    values: list[int] = []
    for request in requests:
        fmt.append(f"BB{len(request.arguments)}i")
        values += (request.command.value, len(request.arguments), *request.arguments)
    return struct.pack("".join(fmt), *values)


def unpack_step(payload: bytes) -> tuple[Request, ...]:
    """The requests of a STEP payload; FrameError for anything malformed."""
    requests: list[Request] = []
    pos, size = 0, len(payload)
    while pos < size:
        if len(requests) >= MAX_STEP_REQUESTS:
            raise FrameError(f"a STEP of more than {MAX_STEP_REQUESTS} requests")
        if pos + 2 > size:
            raise FrameError(f"STEP cut short at byte {pos}")
        code, count = payload[pos], payload[pos + 1]
        pos += 2
        command = _COMMANDS.get(code)
        if command is None:
            raise FrameError(f"STEP request 0x{code:02x} is not a command")
        end = pos + 4 * count
        if end > size:
            raise FrameError(f"STEP request {command.letter!r} lacks its {count} arguments")
        arguments = struct.unpack_from(f"<{count}i", payload, pos) if count else ()
        requests.append(Request(command, arguments))
        pos = end
    if not requests:
        raise FrameError("a STEP needs at least one request")
    return tuple(requests)


def _field(
    request: dict[str, Any], name: str, kind: type | tuple[type, ...], default: Any = None
) -> Any:
    value = request.get(name, default)
    if value is None or isinstance(value, bool) or not isinstance(value, kind):
        raise FrameError(f"field {name!r} = {value!r} is not a {getattr(kind, '__name__', kind)}")
    return value


def parse_request(frame: Frame) -> RobotCall | Fetch:
    """The typed request a frame carries; FrameError for anything malformed."""
    mtype = frame.type
    if mtype is MessageType.STEP:
        return Step(unpack_step(frame.payload))
    if mtype is MessageType.ASCII:
        return Ascii(*unpack_ascii(frame.payload))
    if mtype is MessageType.PING:
        return Ping()
    if mtype is MessageType.BYE:
        return Bye()
    if mtype is MessageType.INFO:
        return Info()
    if mtype is MessageType.CAMERA_CLOSE:
        return CameraClose()
    if mtype is MessageType.FETCH:
        return Fetch(*unpack_fetch(frame.payload))
    request = unpack_json(frame.payload)
    if mtype is MessageType.CAMERA_OPEN:
        width, height = _field(request, "width", int), _field(request, "height", int)
        if not (0 < width <= 8192 and 0 < height <= 8192):
            raise FrameError(f"camera size {width}x{height} is outside 1..8192")
        return CameraOpen(width, height, _field(request, "pixel_format", str))
    if mtype is MessageType.CAMERA_FRAME:
        kind = _field(request, "kind", str, "raw")
        quality = _field(request, "quality", int, 90)
        rotation = _field(request, "rotation", int, 180)
        if kind not in IMAGE_KINDS or not 1 <= quality <= 100 or rotation not in ROTATIONS:
            raise FrameError(
                f"frame kind {kind!r}, quality {quality!r}, rotation {rotation!r}: "
                "raw|jpeg|png, 1..100, 0|90|180|270"
            )
        return CameraFrame(kind, quality, rotation)
    if mtype is MessageType.CAMERA_CONTROL:
        name = _field(request, "name", str)
        value = _field(request, "value", (int, float))
        if name != "fov_rad" and not isinstance(value, int):
            raise FrameError(f"camera control {name!r} takes an integer, not {value!r}")
        if isinstance(value, float) and not math.isfinite(value):
            raise FrameError(f"camera control {name!r} = {value!r} is not finite")
        return CameraControl(name, value)
    raise FrameError(f"{mtype.name} is not a request")


def pack_request(call: RobotCall | Fetch) -> tuple[MessageType, bytes]:
    """The frame type and payload of a typed request (the client's side of parse_request)."""
    if isinstance(call, Step):
        return MessageType.STEP, pack_step(call.requests)
    if isinstance(call, Ascii):
        return MessageType.ASCII, pack_ascii(call.letter, call.lines)
    if isinstance(call, CameraOpen):
        fields = {"width": call.width, "height": call.height, "pixel_format": call.pixel_format}
        return MessageType.CAMERA_OPEN, pack_json(fields)
    if isinstance(call, CameraFrame):
        fields = {"kind": call.kind, "quality": call.quality, "rotation": call.rotation}
        return MessageType.CAMERA_FRAME, pack_json(fields)
    if isinstance(call, CameraControl):
        return MessageType.CAMERA_CONTROL, pack_json({"name": call.name, "value": call.value})
    if isinstance(call, Fetch):
        return MessageType.FETCH, pack_fetch(call.seq, call.offset)
    return _BARE[type(call)], b""


_BARE: dict[type, MessageType] = {
    Ping: MessageType.PING,
    Bye: MessageType.BYE,
    Info: MessageType.INFO,
    CameraClose: MessageType.CAMERA_CLOSE,
}
