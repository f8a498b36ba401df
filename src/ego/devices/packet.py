"""What the families read only from the e-puck2's "all sensors" packet share (-0x08).

The magnetometer, the temperature and the selector have no command of their own over
USB and Bluetooth: they come in the 103-byte packet (MAIN:src/epuck1x/Asercom2.c:
296-468), whose 49 values each such family takes its slice of (ego.serial.asercom2
names every field). Every family asking the packet in one step shares one ``-0x08``
(ego.serial.protocol.encode_batch).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import ClassVar

from ego.devices.base import Sensor
from ego.seam.profile import Command, Profile

__all__ = ["PacketSensor"]


class PacketSensor(Sensor):
    """A sensor family read from the "all sensors" packet: its values are ``fields``."""

    command = Command.ALL_SENSORS
    webots_device = False  # Webots' e-puck2 model has no device for these
    #: Where the family's values lie among the packet's 49.
    fields: ClassVar[slice] = slice(0, 0)

    def __init__(self, profile: Profile) -> None:
        super().__init__(profile)
        self._values: tuple[float, ...] = ()

    @property
    def member_names(self) -> tuple[str, ...]:
        return self.served_names()

    def take(self, values: Sequence[float]) -> None:
        self._values = tuple(values[self.fields])

    def readings(self) -> list[float] | None:
        return [float(v) for v in self._values] if self.has_values else None

    @property
    def packet_values(self) -> tuple[float, ...]:
        """The family's values from the last packet."""
        self.require_values()
        return self._values
