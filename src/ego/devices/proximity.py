"""The eight infra-red proximity sensors ps0..ps7, plus the Overo board's ps8/ps9 (wire N)."""

from __future__ import annotations

from typing import ClassVar

from ego.devices.base import ArraySensor
from ego.serial.protocol import Command, Firmware

__all__ = ["ProximitySensors"]


class ProximitySensors(ArraySensor):
    """IR proximity, 0..~4095, higher is closer; parsed signed (it can dip below 0).

    >>> robot.proximity.enable(64)                       # doctest: +SKIP
    >>> robot.step(64)
    >>> front = max(robot.proximity.value("ps0"), robot.proximity.value("ps7"))
    """

    family = "proximity sensors"
    names: ClassVar[tuple[str, ...]] = tuple(f"ps{i}" for i in range(10))
    command = Command.PROXIMITY
    #: Calibrated IR can dip below 0 (protocol.md: parse signed); far below is corruption.
    value_range: ClassVar[tuple[int, int]] = (-1024, 4095)
    #: protocol.md: the stock Overo firmware adds the long-range IR8 (left) and IR9 (right).
    counts: ClassVar[dict[Firmware, int]] = {Firmware.WEBOTS: 8, Firmware.GCTRONIC: 10}

    @property
    def member_names(self) -> tuple[str, ...]:
        return self.names[: self.counts[self.profile.firmware]]
