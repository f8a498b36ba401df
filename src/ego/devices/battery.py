"""The battery (wire command b), on the firmwares that have it.

docs/protocol.md, quirk "b": only GCtronic's stock firmware answers ``b``, with two bytes
whose meaning depends on the robot. An e-puck revision 1.3 measures its battery with an
ADC and sends the raw count; older robots only have a comparator, and send its flag (1:
the battery is fine, 0: it is below about 3.4 V) and a 0. Webots' firmware has no ``b``,
so enabling the battery there raises UnsupportedDeviceError instead of waiting out a
timeout for a reply that never comes.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence

from ego.devices.base import Sensor, Verdict, out_of_range
from ego.devices.table import TABLE
from ego.errors import UnsupportedDeviceError
from ego.seam.batch import Request
from ego.seam.profile import Command, Profile

__all__ = ["Battery"]


@TABLE.declare("battery", webots_rank=8)
class Battery(Sensor):
    """Battery state: a raw ADC count (rev 1.3) or a low-battery flag (older robots).

    >>> robot.battery.enable(1000)                       # doctest: +SKIP
    >>> robot.step(64); robot.battery.low
    False
    """

    family = "battery"
    command = Command.BATTERY
    webots_device = False

    def __init__(self, profile: Profile) -> None:
        super().__init__(profile)
        self._reading = 0

    def enable(self, period_ms: int, names: Iterable[str] | None = None) -> None:
        """Sample every ``period_ms``; refused where the reply's meaning is unknown."""
        self.require(self.command)
        if self.profile.rev13 is None:
            raise UnsupportedDeviceError(
                "the battery's reply means a count on an e-puck rev 1.3 and a flag on older "
                "ones, and this robot's revision was not asked (the firmware was given, not "
                "probed): open it with firmware='auto' to read the battery"
            )
        super().enable(period_ms, names)

    def validate(self, request: Request, values: Sequence[float], now_s: float) -> Verdict:
        if self.profile.rev13:
            return Verdict(out_of_range("battery", values, 0, 4095))
        return Verdict(out_of_range("battery flag", values, 0, 1))

    def take(self, values: Sequence[float]) -> None:
        self._reading = int(values[0])

    @property
    def raw(self) -> int | None:
        """The ADC count on an e-puck rev 1.3; None where the robot only has a flag."""
        self.require_values()
        return self._reading if self.profile.rev13 else None

    @property
    def low(self) -> bool | None:
        """Whether the battery is low (below about 3.4 V); None on a rev 1.3 (use ``raw``)."""
        self.require_values()
        return None if self.profile.rev13 else self._reading == 0

    @property
    def value(self) -> float:
        """One number for Webots' battery sensor: the raw count, or the flag (1: fine)."""
        self.require_values()
        return float(self._reading)
