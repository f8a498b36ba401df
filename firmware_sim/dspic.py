"""The dsPIC's asercom firmware, byte for byte, for both profiles (no I/O, no clock).

Written from protocol.md independently of ``ego.serial.protocol``, so that a mistake in
the library's tables shows up as a test failure instead of being mirrored here.
Bytes go in with :meth:`Dspic.feed`; what the firmware would send comes out as a list
of :class:`Emission` (the reply of a batch, U's 600 bytes sent at once, an ASCII line).
"""

from __future__ import annotations

import struct
import warnings
from dataclasses import dataclass, field

from firmware_sim.world import World

__all__ = [
    "BANNER",
    "FIRMWARES",
    "FIRMWARE_ALIASES",
    "BatchRecord",
    "Dspic",
    "Emission",
    "firmware_name",
]

#: asercom's welcome text after a reset.
BANNER = (
    b"\x0c\x07 WELCOME to the SerCom protocol on e-Puck\r\n"
    b' the EPFL education robot type "H" for help\r\n'
)
FIRMWARES = ("gctronic", "webots")
#: The profiles' first names, still accepted with a warning.
FIRMWARE_ALIASES = {"thesis": "webots", "gctronic-overo": "gctronic"}


def firmware_name(name: str) -> str:
    """``name`` if it is a firmware of :data:`FIRMWARES`, its new name if an old one."""
    if name in FIRMWARE_ALIASES:
        new = FIRMWARE_ALIASES[name]
        warnings.warn(f"firmware name {name!r} is deprecated: use {new!r}", FutureWarning,
                      stacklevel=3)  # fmt: skip
        return new
    if name not in FIRMWARES:
        raise ValueError(f"firmware {name!r} is not one of {', '.join(FIRMWARES)}")
    return name


_VERSIONS = {
    "webots": "v,Version 1.5.3 November 2016 (Webots)",
    "gctronic": "v,Version 1.2.2 August 2008 GCtronic",
}


def _neg(letter: str) -> int:
    return (-ord(letter)) & 0xFF


@dataclass(slots=True)
class Emission:
    """Bytes the firmware sends, and why (``reply``, ``prefix`` of U, ``ascii``, ``banner``)."""

    data: bytes
    kind: str
    #: For ``reply``: the batch it answers (emitted at every batch end, even when empty).
    record: BatchRecord | None = None


@dataclass(slots=True)
class BatchRecord:
    """Ground truth of one answered batch: what was parsed and what a clean line carries."""

    index: int
    commands: str  # the letters parsed, in order ("aENQ")
    reply: bytes  # prefixes then in-batch replies, before any fault touches them
    faults: list[str] = field(default_factory=list)


# Each command: (argument byte count, handler name). Unknown bytes are skipped silently.
_COMMANDS: dict[int, tuple[int, str]] = {
    _neg("a"): (0, "accel_raw"),
    _neg("A"): (0, "accel_spherical"),
    _neg("D"): (4, "set_speed"),
    _neg("E"): (0, "get_speed"),
    _neg("L"): (2, "set_led"),
    _neg("M"): (0, "floor"),
    _neg("N"): (0, "proximity"),
    _neg("O"): (0, "light"),
    _neg("P"): (4, "set_steps"),
    _neg("Q"): (0, "get_steps"),
    _neg("u"): (0, "mic_amplitude"),
    _neg("U"): (0, "mic_buffer"),
    _neg("b"): (0, "battery"),
    _neg("g"): (0, "gyro"),
}


class Dspic:
    """One dsPIC running asercom in ``firmware`` mode over a :class:`World`."""

    def __init__(self, world: World, firmware: str = "webots", hardware: str = "1.1") -> None:
        self.world = world
        self.firmware = firmware_name(firmware)
        self.hardware = hardware
        self.batches = 0
        self.last_record: BatchRecord | None = None
        self._line: bytearray | None = None  # an ASCII line being received
        self._in_batch = False
        self._pending: tuple[int, int, str] | None = None  # (command, args needed, handler)
        self._args = bytearray()
        self._reply = bytearray()
        self._prefix = bytearray()
        self._letters: list[str] = []

    @property
    def overo(self) -> bool:
        return self.firmware == "gctronic"

    def reset(self) -> None:
        """Power-on state: parser idle, motors stopped, counters and LEDs cleared."""
        self._line = None
        self._in_batch = False
        self._pending = None
        self._args.clear()
        self._reply.clear()
        self._prefix.clear()
        self._letters.clear()
        self.world.reset()

    def feed(self, data: bytes) -> list[Emission]:
        out: list[Emission] = []
        for byte in data:
            self._byte(byte, out)
        return out

    # -- parser ----------------------------------------------------------------------

    def _byte(self, byte: int, out: list[Emission]) -> None:
        if self._line is not None:
            self._line.append(byte)
            if byte == 0x0A:
                line, self._line = bytes(self._line), None
                self._ascii(line, out)
            return
        if not self._in_batch:
            if byte == 0:
                return  # protocol.md: a lone 0x00 outside a batch is ignored
            if byte < 0x80:
                self._line = bytearray([byte])
                if byte == 0x0A:
                    self._line = None
                return
            self._in_batch = True
        if self._pending is not None:
            self._args.append(byte)
            command, needed, handler = self._pending
            if len(self._args) == needed:
                self._pending = None
                self._run(command, handler, bytes(self._args), out)
                self._args.clear()
            return
        if byte == 0:
            self._end_batch(out)
            return
        entry = _COMMANDS.get(byte)
        if entry is None or (entry[1] == "gyro" and not self.overo):
            return  # protocol.md: unknown command bytes are skipped silently
        needed, handler = entry
        if needed:
            self._pending = (byte, needed, handler)
        else:
            self._run(byte, handler, b"", out)

    def _run(self, command: int, handler: str, args: bytes, out: list[Emission]) -> None:
        self._letters.append(chr((-command) & 0xFF))
        getattr(self, "_cmd_" + handler)(args, out)

    def _end_batch(self, out: list[Emission]) -> None:
        self._in_batch = False
        self.batches += 1
        self.last_record = BatchRecord(
            self.batches, "".join(self._letters), bytes(self._prefix + self._reply)
        )
        out.append(Emission(bytes(self._reply), "reply", self.last_record))
        self._reply.clear()
        self._prefix.clear()
        self._letters.clear()

    # -- binary commands ---------------------------------------------------------------

    def _cmd_accel_raw(self, args: bytes, out: list[Emission]) -> None:
        if self.overo and self.hardware == "1.3":
            self._reply += bytes(6)  # protocol.md: that accelerometer is on I2C
        else:
            self._reply += struct.pack("<3H", *self.world.accelerometer_raw())

    def _cmd_accel_spherical(self, args: bytes, out: list[Emission]) -> None:
        if self.overo and self.hardware == "1.3":
            self._reply += bytes(12)
        else:
            self._reply += struct.pack("<3f", *self.world.accelerometer_spherical())

    def _cmd_set_speed(self, args: bytes, out: list[Emission]) -> None:
        self.world.set_speeds(*struct.unpack("<2h", args))

    def _cmd_get_speed(self, args: bytes, out: list[Emission]) -> None:
        self._reply += struct.pack("<2h", *self.world.speeds)

    def _cmd_set_led(self, args: bytes, out: list[Emission]) -> None:
        led, value = args
        if self.overo and led in (8, 9):
            return  # protocol.md: L 8 and L 9 are ignored by the stock Overo firmware
        self.world.set_led(led, value)

    def _cmd_floor(self, args: bytes, out: list[Emission]) -> None:
        if not self.overo:  # protocol.md: M returns nothing on the stock Overo firmware
            self._reply += struct.pack("<3H", *self.world.floor())

    def _cmd_proximity(self, args: bytes, out: list[Emission]) -> None:
        values = self.world.proximity(long_range=self.overo)
        self._reply += struct.pack(f"<{len(values)}h", *values)

    def _cmd_light(self, args: bytes, out: list[Emission]) -> None:
        values = self.world.light(long_range=self.overo)
        self._reply += struct.pack(f"<{len(values)}h", *values)

    def _cmd_set_steps(self, args: bytes, out: list[Emission]) -> None:
        self.world.set_steps(*struct.unpack("<2h", args))

    def _cmd_get_steps(self, args: bytes, out: list[Emission]) -> None:
        self._reply += struct.pack("<2h", *self.world.steps_int16())

    def _cmd_mic_amplitude(self, args: bytes, out: list[Emission]) -> None:
        self._reply += struct.pack("<3H", *self.world.microphone_amplitudes())

    def _cmd_mic_buffer(self, args: bytes, out: list[Emission]) -> None:
        buffers, newest = self.world.microphone_buffer()
        samples = struct.pack("<300h", *(s for buf in buffers for s in buf))
        # protocol.md: the 600 bytes are sent at once when U is parsed, before the
        # batch's other replies; the batch itself carries the newest sample's index.
        self._prefix += samples
        out.append(Emission(samples, "prefix"))
        self._reply.append(newest)

    def _cmd_battery(self, args: bytes, out: list[Emission]) -> None:
        self._reply += struct.pack("<H", self.world.battery_raw)

    def _cmd_gyro(self, args: bytes, out: list[Emission]) -> None:
        self._reply += bytes(6)  # protocol.md: g returns 6 zero bytes on this firmware

    # -- ASCII commands ----------------------------------------------------------------

    def _ascii(self, line: bytes, out: list[Emission]) -> None:
        text = line.decode("ascii", errors="replace").strip()
        if not text:
            return
        letter = text[0].upper()
        lines: list[str]
        if letter == "V":
            lines = [_VERSIONS[self.firmware], f"HW version: {self.hardware}"]
        elif letter == "S":
            self.world.set_speeds(0, 0)
            for i in range(10):
                self.world.set_led(i, 0)
            lines = ["s"]
        elif letter == "C":
            lines = ["c,10" if self.overo else "c,3"]
        elif letter == "K":
            lines = ["k, Starting calibration", "k, Calibration finished"]
        elif letter == "R":
            self.reset()
            out.append(Emission(BANNER, "banner"))
            return
        else:
            lines = ["z,Command not found"]
        out.append(Emission("".join(s + "\r\n" for s in lines).encode("ascii"), "ascii"))
