"""The kernel's SMBus emulation on a plain I2C adapter (i2c-core-smbus.c,
i2c_smbus_xfer_emulated): each SMBus call becomes one or two I2C messages.

The Pi's i2c-bcm2835 has no SMBus engine of its own, so every ``I2C_SMBUS`` ioctl is
turned into messages this way: a write of the command byte (plus data), and for reads a
second, read message in the same transaction. Words go low byte first. PEC (when
``I2C_PEC`` is set) appends a CRC-8 to writes and checks one on reads (``-EBADMSG``).
"""

from __future__ import annotations

import errno
from dataclasses import dataclass

from firmware_sim.pipuck.bus import I2C_M_RD, I2C_M_TEN, Bus, I2cError, Message

__all__ = ["SMBUS_SIZES", "smbus_xfer"]

QUICK, BYTE, BYTE_DATA, WORD_DATA, PROC_CALL, BLOCK_DATA = 0, 1, 2, 3, 4, 5
I2C_BLOCK_BROKEN, BLOCK_PROC_CALL, I2C_BLOCK_DATA = 6, 7, 8
SMBUS_SIZES = frozenset(range(9))
READ, WRITE = 1, 0
BLOCK_MAX = 32
#: include/linux/i2c.h: I2C_CLIENT_PEC.
CLIENT_PEC = 0x04


def _crc8(data: bytes) -> int:
    """The SMBus PEC: CRC-8, polynomial x^8 + x^2 + x + 1 (i2c-core-smbus.c crc8)."""
    crc = 0
    for byte in data:
        crc ^= byte
        for _ in range(8):
            crc = ((crc << 1) ^ 0x07) & 0xFF if crc & 0x80 else (crc << 1) & 0xFF
    return crc


def _block(data: bytes) -> bytearray:
    return bytearray(data[:34].ljust(34, b"\0"))


@dataclass(slots=True)
class _Plan:
    """What i2c_smbus_xfer_emulated sends: the write message's bytes, how many bytes the
    read message asks, how many messages, the direction after PROC_CALL's turn."""

    buf0: bytearray
    read_len: int = 0
    nmsgs: int = 1
    read_write: int = WRITE
    recv_len: bool = False


def _plan(read_write: int, command: int, size: int, block: bytearray) -> _Plan:
    plan = _Plan(bytearray([command]), nmsgs=2 if read_write == READ else 1,
                 read_write=read_write)  # fmt: skip
    reading = read_write == READ
    if size == BYTE and reading:
        plan.nmsgs, plan.buf0, plan.read_len = 1, bytearray(), 1
    elif size == BYTE_DATA:
        if reading:
            plan.read_len = 1
        else:
            plan.buf0.append(block[0])
    elif size == WORD_DATA:
        if reading:
            plan.read_len = 2
        else:
            plan.buf0 += block[0:2]
    elif size == PROC_CALL:
        plan.nmsgs, plan.read_write, plan.read_len = 2, READ, 2
        plan.buf0 += block[0:2]
    elif size in (BLOCK_DATA, BLOCK_PROC_CALL):
        if size == BLOCK_PROC_CALL:
            plan.nmsgs, plan.read_write = 2, READ
        if plan.read_write == READ:
            plan.read_len, plan.recv_len = 1, True
        if size == BLOCK_PROC_CALL or not reading:
            if block[0] > BLOCK_MAX:
                raise I2cError(errno.EINVAL)
            plan.buf0 += block[0 : block[0] + 1]
    elif size == I2C_BLOCK_DATA:
        if block[0] > BLOCK_MAX:
            raise I2cError(errno.EINVAL)
        if reading:
            plan.read_len = block[0]
        else:
            plan.buf0 += block[1 : block[0] + 1]
    elif size != BYTE:
        raise I2cError(errno.EOPNOTSUPP)
    return plan


def smbus_xfer(
    bus: Bus, addr: int, flags: int, read_write: int, command: int, size: int, data: bytes
) -> bytes:
    """One SMBus transfer; ``data`` is the caller's ``union i2c_smbus_data`` (34 bytes,
    zero-padded), returned updated as the kernel leaves it. Raises :class:`I2cError`."""
    flags &= I2C_M_TEN | CLIENT_PEC
    msg_flags = flags & I2C_M_TEN
    block = _block(data)
    if size == QUICK:
        return _quick(bus, addr, msg_flags, read_write, block)
    plan = _plan(read_write, command, size, block)
    pec = bool(flags & CLIENT_PEC) and size != I2C_BLOCK_DATA
    if pec and plan.read_write == WRITE:
        plan.buf0.append(_crc8(bytes([addr << 1]) + bytes(plan.buf0)))
    elif pec:
        plan.read_len += 1  # the target's PEC byte
    messages = []
    if plan.nmsgs == 2 or plan.read_write == WRITE:
        messages.append(Message(addr, msg_flags, len(plan.buf0), bytes(plan.buf0)))
    if plan.read_write == READ:
        # i2c-bcm2835 ignores I2C_M_RECV_LEN: a block read gets its count byte only.
        messages.append(Message(addr, msg_flags | I2C_M_RD, plan.read_len))
    replies = bus.transfer(messages)
    if plan.read_write == WRITE:
        return bytes(block)
    got = replies[-1]
    if pec:
        head = bytes([addr << 1]) + bytes(plan.buf0) if plan.nmsgs == 2 else b""
        if _crc8(head + bytes([addr << 1 | 1]) + got[:-1]) != got[-1]:
            raise I2cError(errno.EBADMSG)
        got = got[:-1]
    return _unpack(size, block, got, plan.recv_len)


def _quick(bus: Bus, addr: int, msg_flags: int, read_write: int, block: bytearray) -> bytes:
    flags = msg_flags | (I2C_M_RD if read_write == READ else 0)
    bus.transfer([Message(addr, flags, 0)])
    return bytes(block)


def _unpack(size: int, block: bytearray, got: bytes, recv_len: bool) -> bytes:
    if size in (BYTE, BYTE_DATA):
        block[0] = got[0]
    elif size in (WORD_DATA, PROC_CALL):
        block[0:2] = got[0:2]
    elif size == I2C_BLOCK_DATA:
        block[1 : 1 + len(got)] = got
    elif recv_len:
        if got[0] > BLOCK_MAX:
            raise I2cError(errno.EPROTO)
        # The count byte, then what the kernel's buffer held: the adapter read no more
        # [inferred: zeros for the kernel's uninitialised stack buffer].
        block[0 : got[0] + 1] = bytes([got[0]]) + bytes(got[0])
    return bytes(block)
