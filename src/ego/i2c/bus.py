"""The I2C seam: what ego needs of a bus, and the real one on /dev/i2c-N (smbus2).

smbus2 is pure Python i2c-dev access (GCtronic's own Linux code for the e-puck reads the
ground module with it: gctronic/Pi-puck, ground-sensor/groundsensor.py). A device that
does not acknowledge its address raises OSError (EREMOTEIO or ENXIO, from the adapter
driver), which :mod:`ego.i2c.side` reads as "not fitted".
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Protocol, runtime_checkable

from ego.errors import OutOfRangeError

if TYPE_CHECKING:
    from smbus2 import SMBus

__all__ = [
    "DEFAULT_I2C_BUS",
    "MAX_BLOCK",
    "I2CAccess",
    "I2CBus",
    "SMBusI2C",
    "given_bus",
    "i2c_bus_path",
    "local_bus",
]

#: The Overo's expansion I2C bus, OMAP3 I2C3 (docs/protocol.md, "The Overo's own I2C bus").
DEFAULT_I2C_BUS = 3
#: The longest SMBus I2C block read.
MAX_BLOCK = 32


@runtime_checkable
class I2CBus(Protocol):
    """One I2C bus as ego uses it: 7-bit addresses, register reads and writes."""

    @property
    def name(self) -> str:
        """Where the bus is ("/dev/i2c-3"), for messages."""
        ...

    def read_block(self, address: int, register: int, count: int) -> bytes:
        """``count`` bytes from ``register`` on, in one transaction (write the register,
        repeated start, read). OSError when the device does not acknowledge."""
        ...

    def write_byte_data(self, address: int, register: int, value: int) -> None:
        """Write one byte to ``register``. OSError when the device does not acknowledge."""
        ...

    def close(self) -> None:
        """Release the bus; idempotent."""
        ...


def i2c_bus_path(bus: int | str) -> str:
    """The device file of bus ``bus``: a number (3: ``/dev/i2c-3``) or a path as given."""
    if isinstance(bus, bool) or not isinstance(bus, (int, str)):
        raise OutOfRangeError(f"I2C bus {bus!r} is not a bus number or a /dev/i2c-N path")
    if isinstance(bus, str) and bus.isdigit():
        bus = int(bus)
    if isinstance(bus, int):
        if not 0 <= bus <= 255:
            raise OutOfRangeError(f"I2C bus {bus} is outside 0..255")
        return f"/dev/i2c-{bus}"
    if not bus.startswith("/"):
        raise OutOfRangeError(f"I2C bus {bus!r} is not a bus number or a /dev/i2c-N path")
    return bus


class SMBusI2C:
    """A Linux I2C bus through i2c-dev (smbus2): ``SMBusI2C(3)`` opens ``/dev/i2c-3``.

    Opening raises OSError (FileNotFoundError when the bus does not exist, PermissionError
    without root or the i2c group).
    """

    def __init__(self, bus: int | str = DEFAULT_I2C_BUS) -> None:
        from smbus2 import SMBus  # imported here: only a robot that uses I2C pays for it

        self._name = i2c_bus_path(bus)
        self._bus: SMBus | None = SMBus(self._name)

    @property
    def name(self) -> str:
        return self._name

    def _open_bus(self) -> SMBus:
        if self._bus is None:
            raise OSError(f"{self._name} is closed")
        return self._bus

    def read_block(self, address: int, register: int, count: int) -> bytes:
        if not 1 <= count <= MAX_BLOCK:
            raise OutOfRangeError(f"I2C block of {count} bytes is outside 1..{MAX_BLOCK}")
        return bytes(self._open_bus().read_i2c_block_data(address, register, count))

    def write_byte_data(self, address: int, register: int, value: int) -> None:
        self._open_bus().write_byte_data(address, register, value)

    def close(self) -> None:
        if self._bus is not None:
            self._bus.close()
            self._bus = None

    def __repr__(self) -> str:
        return f"<SMBusI2C {self._name}>"


@dataclass(frozen=True, slots=True)
class I2CAccess:
    """Where a robot's I2C bus is (for messages) and how to open it, at first need."""

    name: str
    open: Callable[[], I2CBus]


def local_bus(bus: int | str = DEFAULT_I2C_BUS) -> I2CAccess:
    """This machine's ``/dev/i2c-N``: the Overo's own bus when ego runs on the robot."""
    path = i2c_bus_path(bus)
    return I2CAccess(path, lambda: SMBusI2C(path))


def given_bus(bus: I2CBus) -> I2CAccess:
    """A bus already open (an emulator's, a test's): opening it hands it over."""
    return I2CAccess(bus.name, lambda: bus)
