"""The dsPIC's binary protocol as data and pure functions: requests in bytes out, and back.

Nothing here does I/O, so every quirk of docs/protocol.md is tested on bytes alone:

* a command byte is the negative of an ASCII letter, ``(-ord(c)) & 0xFF``;
* a batch ends with 0x00, and only then does the dsPIC answer, all replies back to
  back in command order, with no header, length or checksum;
* a batch of actuator commands only (``D``, ``L``, ``P``) gets no reply at all;
* ``U`` sends its 600 sample bytes at once when parsed, before the batch's replies,
  and adds one byte (the newest sample's index) to them;
* the stock GCtronic firmware in Overo mode answers ``N``/``O`` with 20 bytes, not 16,
  and ``M`` with nothing.

Firmware differences live in the :data:`PROFILES` table, not in ``if`` chains.
"""

from __future__ import annotations

import struct
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from types import MappingProxyType

from ego.core.profile import (
    DEFAULT_BAUD,
    DEPRECATED_FIRMWARE_NAMES,
    FIRMWARE_CHOICES,
    AsciiStop,
    Command,
    Firmware,
    Profile,
    WireFormat,
)
from ego.errors import ExtraBytesError, ShortReplyError, UnsupportedDeviceError

__all__ = [
    "BANNER_MARKER",
    "BITS_PER_BYTE",
    "DEFAULT_BAUD",
    "DEPRECATED_FIRMWARE_NAMES",
    "FIRMWARE_CHOICES",
    "GCTRONIC_BLUETOOTH",
    "MAX_SPEED_STEPS",
    "PROFILES",
    "STEPS_PER_TURN",
    "AsciiStop",
    "Batch",
    "Command",
    "Firmware",
    "Profile",
    "Request",
    "WireFormat",
    "command_byte",
    "encode_batch",
    "parse_batch",
    "reply_sizes",
    "wire_time_s",
]

BITS_PER_BYTE = 10  # 8N1: start + 8 data + stop
STEPS_PER_TURN = 1000
MAX_SPEED_STEPS = 1000
#: Every welcome banner of the firmwares we know contains this; its arrival mid-stream
#: means the dsPIC restarted.
BANNER_MARKER = b"WELCOME"


def command_byte(letter: str) -> int:
    """The binary command byte for an ASCII letter: its negative, modulo 256."""
    if len(letter) != 1 or not letter.isascii():
        raise ValueError(f"a command is one ASCII letter, not {letter!r}")
    return (-ord(letter)) & 0xFF


def wire_time_s(n_bytes: int, baud: int = DEFAULT_BAUD) -> float:
    """How long ``n_bytes`` take on an 8N1 line: 10 bits a byte (43.4 us at 230400)."""
    return n_bytes * BITS_PER_BYTE / baud


def _fmt(arguments: str = "", reply: str = "", prefix: str = "") -> WireFormat:
    return WireFormat(
        struct.Struct("<" + arguments), struct.Struct("<" + reply), struct.Struct("<" + prefix)
    )


_COMMON: dict[Command, WireFormat] = {
    Command.ACCELEROMETER_RAW: _fmt(reply="3H"),
    Command.ACCELEROMETER_SPHERICAL: _fmt(reply="3f"),
    Command.SET_SPEED: _fmt(arguments="2h"),
    Command.GET_SPEED: _fmt(reply="2h"),
    Command.SET_LED: _fmt(arguments="2B"),
    Command.FLOOR: _fmt(reply="3H"),
    Command.PROXIMITY: _fmt(reply="8h"),
    Command.LIGHT: _fmt(reply="8h"),
    Command.SET_STEPS: _fmt(arguments="2h"),
    Command.GET_STEPS: _fmt(reply="2h"),
    Command.MIC_AMPLITUDE: _fmt(reply="3H"),
    Command.MIC_BUFFER: _fmt(reply="B", prefix="300h"),
    Command.BATTERY: _fmt(reply="H"),
}


#: docs/protocol.md, quirk "M": Webots' firmware reads the ground sensors over I2C
#: (about 3 ms), byte by byte; A computes with software floating point on the dsPIC.
_M_WORK_S = 0.003
_A_WORK_S = 0.002

_webots = dict(_COMMON)
# docs/protocol.md, quirk "b": Webots' firmware has no b (the byte is skipped silently).
del _webots[Command.BATTERY]

_overo = dict(_COMMON)
# docs/protocol.md: ps0-ps7 plus the Overo board's long-range IR8 (left) and IR9 (right).
_overo[Command.PROXIMITY] = _fmt(reply="10h")
_overo[Command.LIGHT] = _fmt(reply="10h")
# docs/protocol.md: M returns nothing; the I2C bus is left to the Overo.
del _overo[Command.FLOOR]
#: docs/protocol.md, "The Overo's own I2C bus": in selector 10 the firmware lets the Overo
#: be the I2C master (main_c.c:115-119), so the Overo reads the ground module itself, and,
#: on a rev 1.3, the LSM330 that answers `a` with zeros on the line.
_OVERO_I2C = MappingProxyType(
    {Command.FLOOR: "ground module", Command.ACCELEROMETER_RAW: "LSM330"}
)

_bluetooth = dict(_COMMON)
# docs/protocol.md, quirk "M": the stock firmware is built with its cliff sensors, so
# M answers the three ground sensors and then two cliff values (10 bytes).
_bluetooth[Command.FLOOR] = _fmt(reply="5H")

PROFILES: Mapping[Firmware, Profile] = MappingProxyType(
    {
        Firmware.GCTRONIC: Profile(
            Firmware.GCTRONIC,
            MappingProxyType(_overo),
            tuple(range(8)),  # L 8 and L 9 (body, front) are ignored in Overo mode
            "stock GCtronic asercom, selector 10",
            line_baud=230400,
            work_s=MappingProxyType({Command.ACCELEROMETER_SPHERICAL: _A_WORK_S}),
            calibration_s=1.0,
            ascii_stop=AsciiStop(tuple(range(8)), clears_echo=False),
            i2c=_OVERO_I2C,
        ),
        Firmware.WEBOTS: Profile(
            Firmware.WEBOTS,
            MappingProxyType(_webots),
            tuple(range(10)),
            "Webots e-puck firmware 1.5.x, Bluetooth",
            line_baud=115200,
            work_s=MappingProxyType(
                {Command.FLOOR: _M_WORK_S, Command.ACCELEROMETER_SPHERICAL: _A_WORK_S}
            ),
            calibration_s=1.5,
            ascii_stop=AsciiStop(tuple(range(10)), clears_echo=True),
        ),
    }
)

#: The stock firmware in any selector but 10: asercom over Bluetooth (UART1, 115200).
GCTRONIC_BLUETOOTH = PROFILES[Firmware.GCTRONIC].but(
    commands=MappingProxyType(_bluetooth),
    leds=tuple(range(10)),
    description="stock GCtronic asercom over Bluetooth",
    line_baud=115200,
    work_s=MappingProxyType({Command.FLOOR: _M_WORK_S, Command.ACCELEROMETER_SPHERICAL: _A_WORK_S}),
    i2c=MappingProxyType({}),  # the dsPIC is the I2C master: M and a read it
)


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
            offset += fmt.reply.size
        return values


def encode_batch(requests: Iterable[Request], profile: Profile) -> Batch:
    """The bytes of one step: every request's command and arguments, then 0x00.

    An empty batch encodes to nothing at all (a lone 0x00 would be harmless, but
    sending nothing costs nothing).
    """
    reqs = tuple(requests)
    if not reqs:
        return Batch((), b"", 0, ())
    tx = bytearray()
    formats: list[WireFormat] = []
    for req in reqs:
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
    return Batch(reqs, bytes(tx), reply, tuple(formats))


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
