"""A tiny e-puck2 client for these tests, written from the firmware sources (not from the
emulator): the asercom v2 bytes of MAIN:src/epuck1x/Asercom2.c and the radio's packets of
ESP:Projects/ESP32_E-Puck_2/main/socket_e-puck2.c (MAIN and ESP as in
/work/shared/spec/epuck2.md: e-puck2/e-puck2_main-processor@d2e0dbb and
eshjordan/esp-idf@18f3ae6)."""

from __future__ import annotations

import select
import socket
import struct
import time
from typing import NamedTuple

import serial


def neg(code: str | int) -> int:
    """A binary command byte: the command's code negated (Asercom2.c:292-295)."""
    value = ord(code) if isinstance(code, str) else code
    return (-value) & 0xFF


def batch(*parts: bytes | int | str) -> bytes:
    """Commands (and their argument bytes) then the 0 that ends a batch (Asercom2.c:1042)."""
    out = bytearray()
    for part in parts:
        if isinstance(part, bytes):
            out += part
        else:
            out.append(neg(part))
    return bytes(out + b"\0")


#: socket_e-puck2.c:73 and :171: id 0x80, request, settings, speeds, LEDs, 12 RGB, sound.
COMMAND_SIZE = 21
#: The -0x08 reply (USB/BT: 103 bytes) and the radio's sensor packet (104 bytes), field
#: order of Asercom2.c:296-467, little-endian; the radio moves byte 102 to 103 and puts
#: the button in 102 (uart_e-puck2.c:137-142).
SENSORS = struct.Struct("<3h3f3h3fb8H8HH4H2hHB3BB3H3HB")
assert SENSORS.size == 103


class Sensors(NamedTuple):
    acc: tuple[int, int, int]
    acc_magnitude: float
    orientation: float
    inclination: float
    gyro: tuple[int, int, int]
    magnetometer: tuple[float, float, float]
    temperature: int
    proximity: tuple[int, ...]
    ambient: tuple[int, ...]
    tof_mm: int
    mics: tuple[int, int, int, int]
    steps: tuple[int, int]
    battery: int
    sd: int
    tv: tuple[int, int, int]
    selector: int
    ground: tuple[int, int, int]
    ground_ambient: tuple[int, int, int]
    byte102: int


def parse_sensors(data: bytes) -> Sensors:
    v = SENSORS.unpack(data[:103])
    return Sensors((v[0], v[1], v[2]), v[3], v[4], v[5], (v[6], v[7], v[8]),
                   (v[9], v[10], v[11]), v[12], tuple(v[13:21]), tuple(v[21:29]), v[29],
                   (v[30], v[31], v[32], v[33]), (v[34], v[35]), v[36], v[37],
                   (v[38], v[39], v[40]), v[41], (v[42], v[43], v[44]),
                   (v[45], v[46], v[47]), v[48])  # fmt: skip


def command(
    request: int = 0,
    *,
    settings: int = 0,
    left: int = 0,
    right: int = 0,
    leds: int = 0,
    rgb: tuple[tuple[int, int, int], ...] = ((0, 0, 0),) * 4,
    sound: int = 0,
    packet_id: int = 0x80,
) -> bytes:
    """The 21-byte command (request bit0 image, bit1 sensors; RGB as R, G, B in 0..100)."""
    body = bytes([packet_id, request, settings]) + struct.pack("<hh", left, right)
    body += bytes([leds]) + bytes(c for triple in rgb for c in triple) + bytes([sound])
    assert len(body) == COMMAND_SIZE
    return body


def ask_serial(port: serial.Serial, data: bytes, size: int, timeout_s: float = 5.0) -> bytes:
    """Send ``data`` and read exactly ``size`` bytes (or what came before the timeout)."""
    port.write(data)
    port.timeout = timeout_s
    return bytes(port.read(size))


def sync(port: serial.Serial) -> None:
    """Wait until the firmware has run everything sent so far (-'E' answers 4 bytes)."""
    assert len(ask_serial(port, batch("E"), 4)) == 4


def say(port: serial.Serial, line: bytes) -> bytes:
    """Send an ASCII line and read its answer: up to a first \\r\\n, then what follows
    until the line has been quiet for 0.2 s."""
    port.write(line)
    port.timeout = 5.0
    return bytes(port.read_until(b"\r\n")) + read_quiet(port, 0.2)


def read_quiet(port: serial.Serial, quiet_s: float = 0.3) -> bytes:
    """Everything that arrives until the line has been quiet for ``quiet_s``."""
    previous, port.timeout = port.timeout, quiet_s
    out = b""
    while chunk := port.read(4096):
        out += chunk
    port.timeout = previous
    return out


class WifiClient:
    """A TCP client of the radio: commands out, replies in (id 0x01 image of 38400 bytes,
    0x02 sensors of 104, 0x03 nothing; socket_e-puck2.c:199-276)."""

    def __init__(self, address: tuple[str, int], timeout_s: float = 5.0) -> None:
        self.sock = socket.create_connection(address, timeout=timeout_s)

    def send(self, data: bytes) -> None:
        self.sock.sendall(data)

    def read_exactly(self, size: int) -> bytes:
        out = b""
        while len(out) < size:
            chunk = self.sock.recv(size - len(out))
            if not chunk:
                raise ConnectionError(f"closed after {len(out)} of {size} bytes")
            out += chunk
        return out

    def reply(self) -> tuple[int, bytes]:
        """One reply: its id and its payload."""
        header = self.read_exactly(1)[0]
        size = {0x01: 38400, 0x02: 104, 0x03: 0}[header]
        return header, self.read_exactly(size)

    def sensors(self) -> Sensors:
        header, payload = self.reply()
        assert header == 0x02, f"expected a sensor packet, got id {header:#x}"
        return parse_sensors(payload)

    def nothing_pending(self) -> bool:
        """True if no byte has arrived and the connection is still open; does not wait
        (the caller waits for the events that would have sent something)."""
        readable, _, _ = select.select([self.sock], [], [], 0)
        return not readable  # readable: a byte, or the end of the stream

    def drain(self, seconds: float) -> bytes:
        """Read everything arriving within ``seconds``."""
        end = time.monotonic() + seconds
        out = b""
        while (left := end - time.monotonic()) > 0:
            self.sock.settimeout(left)
            try:
                chunk = self.sock.recv(65536)
            except TimeoutError:
                break
            if not chunk:
                break
            out += chunk
        self.sock.settimeout(5.0)
        return out

    def close(self) -> None:
        self.sock.close()
