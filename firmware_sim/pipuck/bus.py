"""An I2C bus as the Pi's adapter drives it: targets at 7-bit addresses, combined
transactions, and the errors the Raspberry Pi's i2c-bcm2835 returns.

A transaction is a list of messages sent with repeated starts and one stop at the end
(``i2c_transfer``). The adapter sends them in order; a target that does not acknowledge
its address ends the transaction there with ``-EREMOTEIO`` (i2c-bcm2835.c,
bcm2835_i2c_xfer: ``BCM2835_I2C_S_ERR`` -> ``-EREMOTEIO``), after the earlier messages
have reached their targets. The Pi-puck's buses are channels of a PCA9548 mux on the
Pi's bus 1 (yorkrobotlab/pi-puck device-tree/pi-puck.dts:92-161); a mux channel passes
its parent's functionality and errors through (i2c-mux.c), so every bus here answers as
the bcm2835 does.

The wire time of a transaction is counted in bit times at the bus's clock: per message
a start (or repeated start), the address byte and its acknowledge, nine bits a data
byte; one stop [inferred: no clock stretching or gaps between bytes].
"""

from __future__ import annotations

import errno
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Protocol

__all__ = [
    "FUNCS_BCM2835",
    "I2C_M_RD",
    "I2C_M_RECV_LEN",
    "I2C_M_TEN",
    "Bus",
    "I2cError",
    "Message",
    "Target",
]

I2C_M_RD = 0x0001
I2C_M_TEN = 0x0010
I2C_M_RECV_LEN = 0x0400
#: include/uapi/linux/i2c.h: I2C_FUNC_I2C | I2C_FUNC_SMBUS_EMUL, what bcm2835_i2c_func
#: returns (i2c-bcm2835.c): plain I2C, quick, byte, byte data, word data, process
#: call, block write, I2C block read and write, PEC.
FUNCS_BCM2835 = 0x0EFF0009


class I2cError(Exception):
    """A kernel error: ``errno`` is the positive code the system call fails with."""

    def __init__(self, code: int) -> None:
        super().__init__(code, errno.errorcode.get(code, str(code)))
        self.errno = code


class Target(Protocol):
    """A device that answers at an address: what it is written, what it sends back, and
    the stop that ends the transaction (where most firmware acts on what it got)."""

    def write(self, data: bytes) -> None: ...

    def read(self, count: int) -> bytes: ...

    def stop(self) -> None: ...


@dataclass(frozen=True, slots=True)
class Message:
    """One ``struct i2c_msg``: ``data`` is what a write sends; a read asks ``length``."""

    addr: int
    flags: int
    length: int
    data: bytes = b""

    @property
    def is_read(self) -> bool:
        return bool(self.flags & I2C_M_RD)


@dataclass(slots=True)
class Bus:
    """``/dev/i2c-<number>``: its targets by address, and the addresses a kernel driver
    has bound (``I2C_SLAVE`` on those fails with EBUSY, i2c-dev.c i2cdev_check_addr)."""

    number: int
    name: str
    targets: dict[int, Target] = field(default_factory=dict)
    bound: frozenset[int] = frozenset()
    #: Addresses that do not acknowledge even though a target is fitted (a fault).
    silent: set[int] = field(default_factory=set)
    #: Transactions run (ground truth).
    transactions: int = 0
    #: The master's SCL rate, and the wire time all transactions took at it (s).
    clock_hz: int = 100_000
    wire_s: float = 0.0
    #: Called with each transaction's wire time once it ends (pacing), or None.
    on_wire: Callable[[float], None] | None = None

    def target(self, addr: int, flags: int) -> Target | None:
        if flags & I2C_M_TEN or addr in self.silent:
            return None  # the bcm2835 has no 10-bit addressing [inferred: no ACK]
        return self.targets.get(addr)

    def transfer(self, messages: list[Message]) -> list[bytes]:
        """Run one combined transaction; the bytes each read message got, in order."""
        self.transactions += 1
        touched: list[Target] = []
        replies: list[bytes] = []
        bits = 1  # the stop
        try:
            for msg in messages:
                bits += 10  # a (repeated) start, the address byte and its acknowledge
                target = self.target(msg.addr, msg.flags)
                if target is None:
                    raise I2cError(errno.EREMOTEIO)
                bits += 9 * msg.length
                if target not in touched:
                    touched.append(target)
                if msg.is_read:
                    data = bytes(target.read(msg.length))
                    replies.append(data[: msg.length].ljust(msg.length, b"\xff"))
                else:
                    target.write(msg.data)
        finally:
            for target in touched:
                target.stop()
            self._wire(bits / self.clock_hz)
        return replies

    def _wire(self, seconds: float) -> None:
        self.wire_s += seconds
        if self.on_wire is not None:
            self.on_wire(seconds)
