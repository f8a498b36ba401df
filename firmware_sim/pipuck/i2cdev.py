"""The kernel's i2c-dev character device (drivers/i2c/i2c-dev.c) over emulated buses:
open, the ioctls, read and write, with the kernel's checks and error codes.

Written from raspberrypi/linux@049e03d71027297051bc19499082194ce64cdc91
drivers/i2c/i2c-dev.c (i2cdev_read, i2cdev_write, i2cdev_ioctl, i2cdev_ioctl_rdwr,
i2cdev_ioctl_smbus) and the newer kernels' extra check that an ``I2C_RDWR`` carries at
least one message. Sans-I/O: every call returns the system call's result.
"""

from __future__ import annotations

import errno
import os
from collections.abc import Callable
from dataclasses import dataclass

from firmware_sim.pipuck.bus import FUNCS_BCM2835, I2C_M_RD, I2C_M_RECV_LEN, Bus, I2cError, Message
from firmware_sim.pipuck.smbus import CLIENT_PEC, SMBUS_SIZES, smbus_xfer

__all__ = ["I2cDev", "OpenFile"]

I2C_RETRIES, I2C_TIMEOUT, I2C_SLAVE, I2C_TENBIT = 0x0701, 0x0702, 0x0703, 0x0704
I2C_FUNCS, I2C_SLAVE_FORCE, I2C_RDWR, I2C_PEC, I2C_SMBUS = 0x0705, 0x0706, 0x0707, 0x0708, 0x0720
I2C_M_TEN = 0x0010
RDWR_MAX_MSGS = 42  # I2C_RDWR_IOCTL_MAX_MSGS
MAX_TRANSFER = 8192
INT_MAX = 0x7FFF_FFFF
#: Sizes whose data i2c-dev copies in for a read too (i2cdev_ioctl_smbus).
_DATA_SIZES = {1: 1, 2: 1, 3: 2, 4: 2}


@dataclass(slots=True)
class OpenFile:
    """One open ``/dev/i2c-N``: the anonymous client i2c-dev makes at open."""

    bus: Bus
    access: int  # O_RDONLY, O_WRONLY or O_RDWR
    addr: int = 0
    flags: int = 0  # I2C_M_TEN, I2C_CLIENT_PEC


class I2cDev:
    """i2c-dev over the buses ``lookup`` finds (None: no such node, ENOENT)."""

    def __init__(self, lookup: Callable[[int], Bus | None], denied: Callable[[], bool]) -> None:
        self._lookup = lookup
        self._denied = denied

    def open(self, number: int, flags: int) -> OpenFile | int:
        """The open file, or a negative errno: ENOENT without the node, EACCES when the
        caller may not open it (``/dev/i2c-*`` is root:i2c 0660 on Raspberry Pi OS)."""
        bus = self._lookup(number)
        if bus is None:
            return -errno.ENOENT
        if self._denied():
            return -errno.EACCES
        return OpenFile(bus, flags & os.O_ACCMODE)

    def node_state(self, number: int) -> int:
        """For stat and access: 0 (the node is there), -EACCES (there, but the caller
        may not open it), -ENOENT (no node)."""
        if self._lookup(number) is None:
            return -errno.ENOENT
        return -errno.EACCES if self._denied() else 0

    def ioctl(self, file: OpenFile, cmd: int, arg: int) -> int:
        """The ioctls that take a number: I2C_SLAVE(_FORCE), TENBIT, PEC, RETRIES,
        TIMEOUT; anything else is ENOTTY."""
        if cmd in (I2C_SLAVE, I2C_SLAVE_FORCE):
            if arg > 0x3FF or (not file.flags & I2C_M_TEN and arg > 0x7F):
                return -errno.EINVAL
            if cmd == I2C_SLAVE and arg in file.bus.bound:
                return -errno.EBUSY
            file.addr = arg
            return 0
        if cmd == I2C_TENBIT:
            file.flags = file.flags | I2C_M_TEN if arg else file.flags & ~I2C_M_TEN
            return 0
        if cmd == I2C_PEC:
            file.flags = file.flags | CLIENT_PEC if arg else file.flags & ~CLIENT_PEC
            return 0
        if cmd in (I2C_RETRIES, I2C_TIMEOUT):
            return -errno.EINVAL if arg > INT_MAX else 0
        return -errno.ENOTTY

    def funcs(self, file: OpenFile) -> int:
        return FUNCS_BCM2835

    def rdwr(self, file: OpenFile, nmsgs: int, msgs: list[Message]) -> tuple[int, list[bytes]]:
        """I2C_RDWR: the messages' count and, per read message, its ``length`` bytes
        (a ``I2C_M_RECV_LEN`` read keeps the caller's bytes past what was read)."""
        if nmsgs == 0 or nmsgs > RDWR_MAX_MSGS:
            return -errno.EINVAL, []
        sent: list[Message] = []
        for msg in msgs:
            if msg.length > MAX_TRANSFER:
                return -errno.EINVAL, []
            if msg.flags & I2C_M_RECV_LEN:
                first = msg.data[0] if msg.data else 0
                if not msg.is_read or first < 1 or msg.length < first + 32:
                    return -errno.EINVAL, []
                msg = Message(msg.addr, msg.flags, first, msg.data)
            sent.append(msg)
        try:
            got = iter(file.bus.transfer(sent))
        except I2cError as exc:
            return -exc.errno, []
        replies = []
        for original in msgs:
            if original.is_read:
                data = next(got)
                replies.append(data + original.data[len(data) : original.length])
        return len(msgs), replies

    def smbus(
        self, file: OpenFile, read_write: int, command: int, size: int, data: bytes | None
    ) -> tuple[int, bytes]:
        """I2C_SMBUS: 0 and the bytes copied back to the caller's union, or -errno."""
        if size not in SMBUS_SIZES or read_write not in (0, 1):
            return -errno.EINVAL, b""
        no_data = size == 0 or (size == 1 and read_write == 0)
        if data is None and not no_data:
            return -errno.EINVAL, b""
        datasize = _DATA_SIZES.get(size, 34)
        if size == 6:  # I2C_SMBUS_I2C_BLOCK_BROKEN: the old block read, 32 bytes
            size = 8
            if read_write == 1:
                data = bytes([32]) + (data or b"")[1:]
        try:
            block = smbus_xfer(file.bus, file.addr, file.flags, read_write, command, size,
                               data or b"")  # fmt: skip
        except I2cError as exc:
            return -exc.errno, b""
        copy_back = not no_data and (read_write == 1 or size in (4, 7))
        return 0, block[:datasize] if copy_back else b""

    def read(self, file: OpenFile, count: int) -> tuple[int, bytes]:
        """read(2): i2c_master_recv of ``count`` (at most 8192) bytes from the address."""
        if file.access == os.O_WRONLY:
            return -errno.EBADF, b""
        count = min(count, MAX_TRANSFER)
        try:
            (data,) = file.bus.transfer([Message(file.addr, file.flags & I2C_M_TEN | I2C_M_RD,
                                                 count)])  # fmt: skip
        except I2cError as exc:
            return -exc.errno, b""
        return count, data

    def write(self, file: OpenFile, data: bytes) -> int:
        """write(2): i2c_master_send of the bytes to the address."""
        if file.access == os.O_RDONLY:
            return -errno.EBADF
        data = data[:MAX_TRANSFER]
        try:
            file.bus.transfer([Message(file.addr, file.flags & I2C_M_TEN, len(data), data)])
        except I2cError as exc:
            return -exc.errno
        return len(data)
