"""A client process for the Pi-puck emulator's tests, run with the shim preloaded.

It evaluates one Python expression per line of standard input, in a namespace holding
the real smbus2 and the helpers below, and answers one JSON line: the value, or
``{"errno": "EREMOTEIO"}`` when the expression raised an OSError. The test drives it
step by step (pipuck_wire.Client), so that world time can pass between two steps.
"""

from __future__ import annotations

import errno
import fcntl
import json
import os
import struct
import sys
from typing import Any

import smbus2
from smbus2 import SMBus, i2c_msg

I2C_SLAVE = 0x0703
BUSES: dict[int, SMBus] = {}


def bus(number: int) -> SMBus:
    """An SMBus on /dev/i2c-<number>, opened once."""
    if number not in BUSES:
        BUSES[number] = SMBus(number)
    return BUSES[number]


def packet(left: int = 0, right: int = 0, speaker: int = 0, red: int = 0,
           rgb: tuple[int, ...] = (0,) * 12, settings: int = 0,
           checksum: int | None = None) -> list[int]:  # fmt: skip
    """A 20-byte e-puck2 actuator packet, its XOR last (or ``checksum`` if given)."""
    body = struct.pack("<hhBB12BB", left, right, speaker, red, *rgb, settings)
    check = 0
    for byte in body:
        check ^= byte
    return list(body + bytes([check if checksum is None else checksum]))


def exchange(number: int, data: list[int], length: int = 47, addr: int = 0x1F) -> list[int]:
    """One combined transaction: write ``data``, read ``length`` bytes (I2C_RDWR)."""
    write, read = i2c_msg.write(addr, data), i2c_msg.read(addr, length)
    bus(number).i2c_rdwr(write, read)
    return list(read)


def read_only(number: int, length: int = 47, addr: int = 0x1F) -> list[int]:
    read = i2c_msg.read(addr, length)
    bus(number).i2c_rdwr(read)
    return list(read)


def raw_fd(number: int, addr: int, write: list[int], count: int) -> list[int]:
    """os.open, ioctl(I2C_SLAVE), write(2) then read(2): the plain file interface."""
    fd = os.open(f"/dev/i2c-{number}", os.O_RDWR)
    try:
        fcntl.ioctl(fd, I2C_SLAVE, addr)
        os.write(fd, bytes(write))
        return list(os.read(fd, count))
    finally:
        os.close(fd)


def smbus_raw(number: int, addr: int, read_write: int, command: int, size: int,
              block: list[int]) -> list[int]:  # fmt: skip
    """An I2C_SMBUS ioctl with a hand-made union (past smbus2's own checks)."""
    smbus = bus(number)
    smbus._set_address(addr)
    msg = smbus2.smbus2.i2c_smbus_ioctl_data.create(read_write, command, size)
    for i, value in enumerate(block):
        msg.data.contents.block[i] = value
    fcntl.ioctl(smbus.fd, 0x0720, msg)
    return list(msg.data.contents.block)


def main() -> None:
    space: dict[str, Any] = {"SMBus": SMBus, "i2c_msg": i2c_msg, "smbus2": smbus2,
                             "bus": bus, "packet": packet, "exchange": exchange,
                             "read_only": read_only, "raw_fd": raw_fd,
                             "smbus_raw": smbus_raw, "os": os, "fcntl": fcntl,
                             "struct": struct}  # fmt: skip
    print(json.dumps("ready"), flush=True)
    for line in sys.stdin:
        try:
            value: Any = eval(line, space)  # the test's own expressions
        except OSError as exc:
            value = {"errno": errno.errorcode.get(exc.errno or 0, str(exc.errno))}
        if isinstance(value, bytes | bytearray):
            value = list(value)
        print(json.dumps(value), flush=True)


if __name__ == "__main__":
    main()
