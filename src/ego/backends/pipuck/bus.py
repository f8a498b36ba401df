"""The Pi-puck's robot I2C bus on smbus2: the transactions ego makes, and the bus numbers.

smbus2 is i2c-dev in pure Python: a combined transaction is one ``I2C_RDWR`` ioctl
(``i2c_rdwr``, what GCtronic's ``e-puck2/e-puck2_test.py:22-24`` does), the SMBus
transfers are ``I2C_SMBUS`` ioctls. A device that does not acknowledge raises OSError
(EREMOTEIO or ENXIO from the adapter).

Bus numbers (docs/protocol.md, "The Pi-puck"): since the Raspberry Pi Zero 2's kernel
the robot's bus is ``/dev/i2c-12`` and the Pi-puck board's own ``/dev/i2c-11``; older
kernels (Debian Buster and before) named them 4 and 3 (York's
``python-library/pipuck/epuck.py:7-8``, GCtronic's demos, epuck_ros2 PR 31).
:func:`open_buses` tries the current numbers, then the legacy ones.
"""

from __future__ import annotations

import errno
from typing import TYPE_CHECKING, Final

from ego.errors import OutOfRangeError, PortNotFoundError

if TYPE_CHECKING:
    from smbus2 import SMBus

__all__ = ["BUSES", "RobotBus", "i2c_failure", "open_buses"]

#: (robot bus, board bus): current kernels first, then the legacy numbering.
BUSES: Final = {"current": (12, 11), "legacy": (4, 3)}


def open_buses(robot_bus: int | None) -> tuple[RobotBus, int]:
    """The robot's bus, opened, and the board's bus number: ``robot_bus`` if given (the
    board's is one less, as on both numberings), else the first numbering whose robot bus
    opens, as York's library tries them (an open, not a look at ``/dev``: what answers is
    what counts); PortNotFoundError naming both, and what enables I2C, when neither does."""
    if robot_bus is not None:
        return RobotBus(robot_bus), robot_bus - 1
    for robot, board in BUSES.values():
        try:
            return RobotBus(robot), board
        except _Missing:
            continue  # the other numbering; a bus that exists but refuses us is said
    tried = " nor ".join(f"/dev/i2c-{r}" for r, _ in BUSES.values())
    raise PortNotFoundError(
        f"pipuck: neither {tried} exists: is this a Pi-puck with I2C enabled "
        "(raspi-config, Interface Options, I2C; the Pi-puck's device tree overlay in "
        "/boot/config.txt)? Name the bus with the i2c_bus option if it is another"
    )


def i2c_failure(exc: OSError, where: str) -> str:
    """What an OSError of i2c-dev means, in one line."""
    if exc.errno in (errno.EACCES, errno.EPERM):
        return (f"{where}: permission denied: add this user to the i2c group "
                "(sudo adduser $USER i2c, then log in again)")  # fmt: skip
    if exc.errno in (errno.EREMOTEIO, errno.ENXIO, errno.EIO):
        return f"{where}: no answer (the device did not acknowledge its address)"
    return f"{where}: {exc.strerror or exc}"


class _Missing(PortNotFoundError):
    """A bus that does not exist (PortNotFoundError, a FileNotFoundError too)."""


class RobotBus:
    """One ``/dev/i2c-N`` through smbus2, with the transfers the Pi-puck needs."""

    def __init__(self, bus: int) -> None:
        from smbus2 import SMBus  # only a Pi-puck pays for it

        if not 0 <= bus <= 255:
            raise OutOfRangeError(f"I2C bus {bus} is outside 0..255")
        self.path = f"/dev/i2c-{bus}"
        try:
            self._bus: SMBus | None = SMBus(self.path)
        except FileNotFoundError:
            raise _Missing(f"pipuck: {self.path} does not exist") from None
        except OSError as exc:
            raise PortNotFoundError(i2c_failure(exc, f"pipuck: {self.path}")) from None
        #: Bytes on the wire so far, addresses included (what the bus's time is made of).
        self.wire_bytes = 0

    def _open(self) -> SMBus:
        if self._bus is None:
            raise OSError(errno.EBADF, f"{self.path} is closed")
        return self._bus

    def transaction(self, address: int, write: bytes, read_count: int) -> bytes:
        """Write ``write``, then with a repeated start read ``read_count`` bytes: one
        ``I2C_RDWR`` ioctl."""
        from smbus2 import i2c_msg

        out = i2c_msg.write(address, write)
        back = i2c_msg.read(address, read_count)
        self._open().i2c_rdwr(out, back)
        self.wire_bytes += 2 + len(write) + read_count
        return bytes(back)

    def read_word(self, address: int, register: int) -> int:
        """SMBus read word: the register, then its low and high byte."""
        value = int(self._open().read_word_data(address, register))
        self.wire_bytes += 5
        return value

    def write_word(self, address: int, register: int, value: int) -> None:
        """SMBus write word: the register, then the low and the high byte."""
        self._open().write_word_data(address, register, value)
        self.wire_bytes += 4

    def read_byte(self, address: int, register: int) -> int:
        value = int(self._open().read_byte_data(address, register))
        self.wire_bytes += 4
        return value

    def write_byte(self, address: int, register: int, value: int) -> None:
        self._open().write_byte_data(address, register, value)
        self.wire_bytes += 3

    def read_block(self, address: int, register: int, count: int) -> bytes:
        """``count`` bytes from ``register`` on, in one transaction."""
        data = bytes(self._open().read_i2c_block_data(address, register, count))
        self.wire_bytes += 3 + count
        return data

    def close(self) -> None:
        if self._bus is not None:
            self._bus.close()
            self._bus = None
