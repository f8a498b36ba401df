"""The dsPIC's asercom firmware, byte for byte, for both profiles (no I/O, no clock).

Written from docs/protocol.md independently of ``ego.serial.protocol``, so that a mistake in
the library's tables shows up as a test failure instead of being mirrored here.
Bytes go in with :meth:`Dspic.feed`; what the firmware would send comes out as a list
of :class:`Emission` (the reply of a batch, U's 600 bytes sent at once, an ASCII line).
"""

from __future__ import annotations

import struct
from dataclasses import dataclass, field

from firmware_sim.world import World

__all__ = [
    "BANNER",
    "FIRMWARES",
    "BatchRecord",
    "Dspic",
    "Emission",
    "firmware_name",
]

#: Both firmwares' welcome text after a reset (Asercom.c and firmware.c, the
#: uart_send_static_text before the main loop): form feed, bell, no spaces.
BANNER = (
    b"\x0c\x07WELCOME to the SerCom protocol on e-Puck\r\n"
    b'the EPFL education robot type "H" for help\r\n'
)
K_STARTED = b"k, Starting calibration - Remove any object in sensors range\r\n"
K_FINISHED = b"k, Calibration finished\r\n"
#: An LED number past 9: e_set_led then sets every ring LED (e_led.c).
RING = 10
#: The selector position of the Overo mode (Asercom.c: `if (selector == 10) use_bt = 0`).
OVERO_SELECTOR = 10
#: ASCII K: how long each firmware calibrates, deaf to the line (busy loops of Asercom.c
#: and firmware.c's calibrate_ir_sensors at the dsPIC's 14.7 MIPS; measured figures are
#: about 1 s and 1.5 s).
CALIBRATION_S = {"gctronic": 1.0, "webots": 1.5}
#: Firmware time before a command's reply can go: firmware.c reads the ground sensors
#: byte by byte over I2C (about 3 ms); A runs software floating point (inferred, ~2 ms).
WORK_S = {"M": 0.003, "A": 0.002}
#: Asercom.c, the RC5 table: (left, right) speeds for keys 1-9 (SPEED_IR = 600).
RC5_SPEEDS = {
    1: (300, 600), 2: (600, 600), 3: (600, 300), 4: (-600, 600), 5: (0, 0),
    6: (600, -600), 7: (-300, -600), 8: (-600, -600), 9: (-600, -300),
}  # fmt: skip
FIRMWARES = ("gctronic", "webots")


def firmware_name(name: str) -> str:
    """``name`` if it is a firmware of :data:`FIRMWARES`; ValueError else."""
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
    #: The dsPIC's own time before these bytes can go out (I2C reads, K's calibration).
    after_s: float = 0.0
    #: How long the dsPIC then ignores the line (K calibrating).
    deaf_s: float = 0.0


@dataclass(slots=True)
class BatchRecord:
    """Ground truth of one answered batch: what was parsed and what a clean line carries."""

    index: int
    commands: str  # the letters parsed, in order ("aENQ")
    reply: bytes  # prefixes then in-batch replies, before any fault touches them
    faults: list[str] = field(default_factory=list)
    #: The dsPIC's work on the batch before it answers (WORK_S of its commands).
    work_s: float = 0.0


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
    _neg("t"): (0, "temperature"),
}
#: Commands only the stock firmware has (firmware.c's switch has no case for them, so
#: Webots' firmware skips their byte silently).
_STOCK_ONLY = {"battery", "gyro", "temperature"}


class Dspic:
    """One dsPIC running ``firmware`` over a :class:`World`, as the robot it is fitted to.

    ``hardware_version`` is the EEPROM word V reports; ``rev13`` an e-puck revision 1.3
    (I2C accelerometer, battery ADC); ``selector`` the rotary switch (the stock firmware
    talks to the Overo in 10, over Bluetooth in any other); ``ground_module`` whether the
    floor sensors' board is fitted.
    """

    def __init__(
        self,
        world: World,
        firmware: str = "webots",
        hardware_version: int = 0xFFFF,
        *,
        rev13: bool = False,
        selector: int | None = None,
        ground_module: bool = True,
        work: bool = True,
    ) -> None:
        self.world = world
        self.firmware = firmware_name(firmware)
        if not 0 <= hardware_version <= 0xFFFF:
            raise ValueError(f"hardware version {hardware_version} is not a 16-bit word")
        self.hardware_version = hardware_version
        self.rev13 = rev13
        default_selector = OVERO_SELECTOR if self.firmware == "gctronic" else 3
        self.selector = default_selector if selector is None else selector
        if not 0 <= self.selector <= 15:
            raise ValueError(f"selector {self.selector} is not one of 0..15")
        self.ground_module = ground_module
        #: Whether the firmware's modelled time is spent: WORK_S before a reply, and K's
        #: calibration (CALIBRATION_S). Off, the emulator answers as soon as the line lets
        #: it, and a benchmark sees the client's own cost.
        self.work = work
        self.batches = 0
        self.last_record: BatchRecord | None = None
        #: The speeds E echoes: what D last asked, unclamped (Asercom.c: speedl, speedr).
        self.echo = (0, 0)
        self._line: bytearray | None = None  # an ASCII line being received
        self._in_batch = False
        self._pending: tuple[int, int, str] | None = None  # (command, args needed, handler)
        self._args = bytearray()
        self._reply = bytearray()
        self._prefix = bytearray()
        self._letters: list[str] = []

    @property
    def overo(self) -> bool:
        """The stock firmware in selector 10: UART2 to the Overo, I2C left to the Overo."""
        return self.firmware == "gctronic" and self.selector == OVERO_SELECTOR

    @property
    def line_baud(self) -> int:
        """The UART rate this firmware answers at: 230400 to the Overo, else 115200."""
        return 230400 if self.overo else 115200

    def reset(self) -> None:
        """Power-on state: parser idle, motors stopped, counters and LEDs cleared."""
        self._line = None
        self._in_batch = False
        self._pending = None
        self._args.clear()
        self._reply.clear()
        self._prefix.clear()
        self._letters.clear()
        self.echo = (0, 0)
        self.world.reset()

    def rc5_key(self, key: int) -> None:
        """A TV remote's key 0-9 seen by the IR receiver: it drives in every mode (Asercom.c)."""
        left, right = RC5_SPEEDS.get(key, (0, 0))
        self.echo = (left, right)
        self.world.set_speeds(left, right)

    def feed(self, data: bytes) -> list[Emission]:
        out: list[Emission] = []
        for byte in data:
            self._byte(byte, out)
        return out

    # -- parser ----------------------------------------------------------------------

    def _byte(self, byte: int, out: list[Emission]) -> None:
        if self._line is not None:
            self._line.append(byte)
            if byte in (0x0A, 0x0D):  # Asercom.c: `while (c != '\n' && c != '\r')`
                line, self._line = bytes(self._line), None
                self._ascii(line, out)
            return
        if not self._in_batch:
            if byte == 0:
                return  # a lone 0x00 outside a batch is ignored
            if byte < 0x80:
                # Asercom.c skips the \n and \r that start a line (the end of the last).
                if byte not in (0x0A, 0x0D):
                    self._line = bytearray([byte])
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
        if entry is None or (entry[1] in _STOCK_ONLY and self.firmware != "gctronic"):
            return  # both firmwares' `default: // silently ignored`
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
        letters = "".join(self._letters)
        self.last_record = BatchRecord(
            self.batches,
            letters,
            bytes(self._prefix + self._reply),
            work_s=sum(WORK_S.get(c, 0.0) for c in letters if self._does_work(c))
            if self.work
            else 0.0,
        )
        out.append(Emission(bytes(self._reply), "reply", self.last_record))
        self._reply.clear()
        self._prefix.clear()
        self._letters.clear()

    def _does_work(self, letter: str) -> bool:
        return not (letter == "M" and self.overo)  # M sends nothing in Overo mode

    # -- binary commands ---------------------------------------------------------------

    def _acc_scale(self) -> tuple[int, int]:
        """e_acc.c: 0 g and counts a g of this robot's accelerometer."""
        return (2048, 750) if self.rev13 else (2000, 800)

    def _cmd_accel_raw(self, args: bytes, out: list[Emission]) -> None:
        if self.overo and self.rev13:
            self._reply += bytes(6)  # Asercom.c 'a': `if(isEpuckVersion1_3())` zeros
        else:
            self._reply += struct.pack("<3H", *self.world.accelerometer_raw(*self._acc_scale()))

    def _cmd_accel_spherical(self, args: bytes, out: list[Emission]) -> None:
        if self.overo and self.rev13:
            self._reply += bytes(12)  # Asercom.c 'A': 0.0, 0.0, 0.0
        else:
            # Asercom.c / firmware.c 'A': acceleration, orientation, inclination.
            values = self.world.accelerometer_spherical(*self._acc_scale())
            self._reply += struct.pack("<3f", *values)

    def _cmd_set_speed(self, args: bytes, out: list[Emission]) -> None:
        self.echo = struct.unpack("<2h", args)  # E echoes what was asked, unclamped
        self.world.set_speeds(*self.echo)

    def _cmd_get_speed(self, args: bytes, out: list[Emission]) -> None:
        self._reply += struct.pack("<2h", *self.echo)

    def _cmd_set_led(self, args: bytes, out: list[Emission]) -> None:
        led, value = args
        if self.overo and led in (8, 9):
            return  # Asercom.c 'L': body and front LEDs only `if (use_bt)`
        self.world.set_led(led, value)

    def _cmd_floor(self, args: bytes, out: list[Emission]) -> None:
        if self.overo:
            return  # Asercom.c 'M': the I2C bus is the Overo's; nothing is sent
        # Without the module, no device acknowledges and every byte reads 0xFF.
        values = self.world.floor() if self.ground_module else [0xFFFF] * 3
        if self.firmware == "gctronic":
            # Asercom.c 'M' under CLIFF_SENSORS: 4 more bytes, two cliff readings. Their
            # meaning is not in the source; the outer ground sensors stand in for them.
            values = [*values, values[0], values[2]]
        self._reply += struct.pack(f"<{len(values)}H", *values)

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
        buffers, next_slot = self.world.microphone_buffer()
        samples = struct.pack("<300H", *(s for buf in buffers for s in buf))
        # Asercom.c 'U': e_send_uart_char(e_mic_scan, 600) at once, before the batch's
        # replies; the batch then carries e_last_mic_scan_id, the slot written next.
        self._prefix += samples
        out.append(Emission(samples, "prefix"))
        self._reply.append(next_slot)

    def _cmd_battery(self, args: bytes, out: list[Emission]) -> None:
        if self.rev13:  # Asercom.c 'b': getBatteryValueRaw(), low byte first
            self._reply += struct.pack("<H", self.world.battery_raw)
        else:  # BATT_LOW (1: fine, 0: below 3.4 V), then a 0
            self._reply += bytes([1, 0])

    def _cmd_gyro(self, args: bytes, out: list[Emission]) -> None:
        self._reply += bytes(6)  # Asercom.c 'g': zeros unless use_bt on a rev 1.3

    def _cmd_temperature(self, args: bytes, out: list[Emission]) -> None:
        self._reply += bytes(1)  # Asercom.c 't': 0 unless use_bt on a rev 1.3

    # -- ASCII commands ----------------------------------------------------------------

    def _ascii(self, line: bytes, out: list[Emission]) -> None:
        text = line.decode("ascii", errors="replace").strip()
        if not text:
            return
        letter = text[0] if text[0] in "bg" and self.firmware == "gctronic" else text[0].upper()
        lines: list[str]
        if letter == "V":
            lines = [_VERSIONS[self.firmware], f"HW version: {self.hardware_version:X}"]
        elif letter == "S":
            self.world.set_speeds(0, 0)
            if self.firmware == "gctronic":
                # Asercom.c 'S': speeds 0 and e_set_led(8, 0), which is the whole ring
                # for e_set_led; speedl/speedr, which E echoes, are left as they were.
                self.world.set_led(RING, 0)
            else:
                # Webots' S also forgets the commanded speeds and clears every LED.
                self.echo = (0, 0)
                for i in range(10):
                    self.world.set_led(i, 0)
            lines = ["s"]
        elif letter == "C":
            lines = [f"c,{self.selector}"]
        elif letter == "b" and self.firmware == "gctronic":
            # Asercom.c ASCII 'b': "b,RAW (P%)" on a rev 1.3, else "b,BATT_LOW".
            lines = [f"b,{self.world.battery_raw} (76%)" if self.rev13 else "b,1"]
        elif letter == "K":
            # Both firmwares: a first line, the calibration (deaf to the line), a last line.
            out.append(Emission(K_STARTED, "ascii"))
            delay = CALIBRATION_S[self.firmware] if self.work else 0.0
            out.append(Emission(K_FINISHED, "ascii", after_s=delay, deaf_s=delay))
            return
        elif letter == "R":
            self.reset()
            out.append(Emission(b"r\r\n" + BANNER, "banner"))  # Asercom.c 'R': "r" first
            return
        else:
            lines = ["z,Command not found"]
        out.append(Emission("".join(s + "\r\n" for s in lines).encode("ascii"), "ascii"))
