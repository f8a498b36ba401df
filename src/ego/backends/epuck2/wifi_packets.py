"""The e-puck2 radio module's TCP packets, both ways, as bytes in and values out (no I/O).

The radio's WiFi firmware (selector 15) listens on TCP port 1000 and relays between the
PC and the main processor's asercom v2 (``ego.serial.asercom2``). Sources, by short name:

* ESP = ``eshjordan/esp-idf@18f3ae6752d73117ebdb1ed7a2e109326d8dbe1b:Projects/ESP32_E-Puck_2/main/``
  (GCtronic's radio-module WiFi firmware, last commit 2019-02-15);
* MAIN = ``e-puck2/e-puck2_main-processor@d2e0dbba8f50a0619b01186c5437e3f5ffffae56``.

PC to robot, always 21 bytes (ESP:socket_e-puck2.h:14 ``ACTUATORS_BUFF_LEN 21``; the
fields are listed at socket_e-puck2.c:73)::

    0      0x80, the only id that counts as a valid command (socket_e-puck2.c:171)
    1      request: bit 0 stream the image, bit 1 stream the sensors, 0 = an empty
           reply (socket_e-puck2.c:189-195)
    2..20  the asercom ``-0x09`` payload, copied as it is (uart_e-puck2.c:46)

Robot to PC, a header byte and its payload (socket_e-puck2.c:199-276)::

    0x01   38400 bytes: the 160x120 image, RGB565 big-endian (206-226; MAX_BUFF_SIZE 29)
    0x02   104 bytes: the sensors (244-251; uart_e-puck2.h:15)
    0x03   nothing: the request byte was 0 (266-270)

The traps, which a backend must handle (docs/protocol.md, "e-puck2"): the robot sends
nothing until one valid command arrived and wedges if a client leaves before that
(socket_e-puck2.c:164-196); afterwards it re-applies the last command every loop and
keeps streaming; and a stop sent just before closing can be lost.
"""

from __future__ import annotations

import enum
from collections import deque
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Final

from ego.errors import FrameError, OutOfRangeError, ProtocolError
from ego.serial.asercom2 import (
    ACTUATORS_SIZE,
    WIFI_SENSORS_SIZE,
    SensorLayout,
    SensorPacket,
    decode_sensors,
)

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

__all__ = [
    "COMMAND_ID",
    "COMMAND_SIZE",
    "DEFAULT_PORT",
    "IMAGE_HEIGHT",
    "IMAGE_SIZE",
    "IMAGE_WIDTH",
    "NEED_DATA",
    "PAYLOAD_SIZES",
    "Closed",
    "EmptyReply",
    "ImageReply",
    "NeedData",
    "Reply",
    "ReplyKind",
    "ReplyParser",
    "Request",
    "SensorReply",
    "encode_command",
    "image_to_rgb888",
]

#: The robot's TCP port (ESP:socket_e-puck2.c:27 ``TCP_PORT 1000``).
DEFAULT_PORT: Final = 1000
#: The first byte of every command (ESP:socket_e-puck2.c:171).
COMMAND_ID: Final = 0x80
#: A command's size: id, request, the 19-byte actuator payload (ESP:socket_e-puck2.h:14).
COMMAND_SIZE: Final = 2 + ACTUATORS_SIZE
#: The camera as selector 15 sets it up: 640x480 subsampled by 4 in each direction,
#: colour, so 160x120 RGB565 (MAIN:src/main.c:839).
IMAGE_WIDTH: Final = 160
IMAGE_HEIGHT: Final = 120
#: ESP:socket_e-puck2.c:29 ``MAX_BUFF_SIZE 38400 // For the image``.
IMAGE_SIZE: Final = IMAGE_WIDTH * IMAGE_HEIGHT * 2


class Request(enum.IntFlag):
    """Byte 1 of a command: what the robot streams back (ESP:socket_e-puck2.c:189-195).

    ``Request(0)`` asks for an empty ``0x03`` reply: a way to see a command answered
    without reading an image.
    """

    IMAGE = 0x01
    SENSORS = 0x02


def encode_command(request: Request, payload: bytes) -> bytes:
    """The 21-byte command: 0x80, ``request``, then a 19-byte ``-0x09`` payload.

    ``payload`` comes from ``ego.serial.asercom2`` (``ActuatorEncoder.next_payload()``
    or ``encode_actuators``), which validated its values.
    """
    if isinstance(request, bool) or not isinstance(request, int) or not 0 <= request <= 3:
        raise OutOfRangeError(f"request {request!r} is not a combination of Request flags")
    if len(payload) != ACTUATORS_SIZE:
        raise OutOfRangeError(f"actuator payload is {ACTUATORS_SIZE} bytes, not {len(payload)}")
    return bytes((COMMAND_ID, int(request))) + bytes(payload)


# -- replies ----------------------------------------------------------------------------


class ReplyKind(enum.IntEnum):
    """A reply's header byte (ESP:socket_e-puck2.c:206, 244, 268)."""

    IMAGE = 0x01
    SENSORS = 0x02
    EMPTY = 0x03


#: The payload that follows each header.
PAYLOAD_SIZES: Final = {
    ReplyKind.IMAGE: IMAGE_SIZE,
    ReplyKind.SENSORS: WIFI_SENSORS_SIZE,
    ReplyKind.EMPTY: 0,
}


@dataclass(frozen=True, slots=True)
class ImageReply:
    """One camera frame: 38400 bytes of 160x120 RGB565, big-endian (see image_to_rgb888)."""

    data: bytes


@dataclass(frozen=True, slots=True)
class SensorReply:
    """One sensor packet, decoded (the 104-byte WiFi layout), and its bytes."""

    sensors: SensorPacket
    data: bytes = field(repr=False)


@dataclass(frozen=True, slots=True)
class EmptyReply:
    """The answer to a command whose request byte was 0."""


class NeedData:
    """``next_event()``'s answer when no whole packet is buffered yet."""

    def __repr__(self) -> str:
        return "NEED_DATA"


class Closed:
    """``next_event()``'s answer after the robot closed the stream between packets."""

    def __repr__(self) -> str:
        return "CLOSED"


NEED_DATA: Final = NeedData()
CLOSED: Final = Closed()

Reply = ImageReply | SensorReply | EmptyReply


class ReplyParser:
    """Whole replies cut out of the robot's byte stream, fed in chunks of any size.

    h11's shape: :meth:`receive_data` with what ``recv`` returned (``b""`` at the end
    of the stream), then :meth:`next_event` until it returns :data:`NEED_DATA`::

        parser = ReplyParser()
        parser.receive_data(sock.recv(65536))
        while not isinstance(event := parser.next_event(), NeedData):
            handle(event)

    An unknown header, a sensor packet with bytes the firmware never sends, or a stream
    that ends inside a packet raises FrameError; there is no way to find the next
    packet after that, so the parser stays broken and raises it again.
    """

    def __init__(self) -> None:
        self._buf = bytearray()
        self._ended = False
        self._error: FrameError | None = None
        self._ready: deque[Reply] = deque()

    @property
    def buffered(self) -> int:
        """Bytes of an incomplete reply held back."""
        return len(self._buf)

    def receive_data(self, data: bytes | bytearray | memoryview) -> None:
        """Add bytes from the stream; ``b""`` says the robot closed it."""
        if self._error is not None:
            raise self._error
        if self._ended:
            raise FrameError("data after the end of the robot's stream")
        if not data:
            self._ended = True
            return
        self._buf += data

    def next_event(self) -> Reply | NeedData | Closed:
        """The next whole reply, NEED_DATA, or CLOSED once the stream ended cleanly."""
        if self._error is not None:
            raise self._error
        try:
            return self._next()
        except FrameError as exc:
            self._error = exc
            self._buf.clear()
            raise

    def _next(self) -> Reply | NeedData | Closed:
        buf = self._buf
        if not buf:
            return CLOSED if self._ended else NEED_DATA
        try:
            kind = ReplyKind(buf[0])
        except ValueError:
            raise FrameError(
                f"e-puck2 reply header 0x{buf[0]:02X} is not 0x01 (image), 0x02 (sensors)"
                " or 0x03 (empty)"
            ) from None
        size = 1 + PAYLOAD_SIZES[kind]
        if len(buf) < size:
            if self._ended:
                raise FrameError(
                    f"the robot closed the stream inside {kind.name.lower()} reply"
                    f" ({len(buf) - 1} of {size - 1} bytes)"
                )
            return NEED_DATA
        payload = bytes(buf[1:size])
        del buf[:size]
        if kind is ReplyKind.IMAGE:
            return ImageReply(payload)
        if kind is ReplyKind.SENSORS:
            try:
                return SensorReply(decode_sensors(payload, SensorLayout.WIFI), payload)
            except ProtocolError as exc:
                raise FrameError(str(exc)) from exc
        return EmptyReply()


# -- the image --------------------------------------------------------------------------


def image_to_rgb888(
    data: bytes | bytearray | memoryview,
    rotation: int = 0,
    out: npt.NDArray[np.uint8] | None = None,
) -> npt.NDArray[np.uint8]:
    """A 160x120 big-endian RGB565 frame as (120, 160, 3) RGB888, through ego's exact
    converter (``ego.camera.convert.rgb565_to_rgb888``, thesis tables, vectorised).

    The byte order is the clients' reading: both UNIFR's and Webots' converters take red
    from the first byte's top five bits (docs/protocol.md, "e-puck2"); the firmware
    passes the camera's bytes through unchanged. ``rotation`` defaults to 0 [ego's
    choice: neither client rotates the e-puck2's frame].
    """
    if len(data) != IMAGE_SIZE:
        raise FrameError(f"an e-puck2 image is {IMAGE_SIZE} bytes, not {len(data)}")
    # Imported here: OpenCV and numpy are needed only once a frame arrives.
    from ego.camera.convert import rgb565_to_rgb888

    return rgb565_to_rgb888(data, IMAGE_WIDTH, IMAGE_HEIGHT, rotation, byteorder="big", out=out)
