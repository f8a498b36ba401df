"""The e-puck2's magnetometer (in the "all sensors" packet, switched on by -0x0F).

The MPU-9250's magnetometer answers x, y, z in microtesla, float32 (MAIN:src/epuck1x/
Asercom2.c:366-374, src/sensors/imu.h:171-178). Over USB and Bluetooth the firmware
leaves it off, reading 0.0, until ``-0x0F`` with 1 (Asercom2.c:633-662; over USB that
command sleeps 10 ms): enabling the family sends it once, and again after a restart.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence

from ego.devices.base import Verdict
from ego.devices.packet import PacketSensor
from ego.devices.table import TABLE, Series
from ego.seam.batch import Request
from ego.seam.profile import Command, Profile

__all__ = ["Magnetometer"]

#: The AK8963's range is +-4912 uT: beyond it a value is a corrupted byte.
MAX_FIELD_UT = 4912.0


@TABLE.declare("magnetometer", webots_rank=11, series=Series("magnetometer", "µT", ("x", "y", "z")))
class Magnetometer(PacketSensor):
    """The magnetic field, x, y, z in µT.

    >>> robot.magnetometer.enable(100)                   # doctest: +SKIP
    >>> robot.step(100); robot.magnetometer.values
    (0.0, 21.0, -43.0)
    """

    family = "magnetometer"
    fields = slice(9, 12)

    def __init__(self, profile: Profile) -> None:
        super().__init__(profile)
        self._switch_on = False

    def enable(self, period_ms: int, names: Iterable[str] | None = None) -> None:
        """Sample the field every ``period_ms``; the first step switches it on (-0x0F 1)."""
        self.require(Command.MAGNETOMETER_ENABLE)
        was = self.enabled
        super().enable(period_ms, names)
        self._switch_on = self._switch_on or not was

    def plan(self, now_ms: int) -> list[Request]:
        first = [Request(Command.MAGNETOMETER_ENABLE, (1,))] if self._switch_on else []
        return first + super().plan(now_ms)

    def validate(self, request: Request, values: Sequence[float], now_s: float) -> Verdict:
        if request.command is Command.MAGNETOMETER_ENABLE:
            return Verdict(None if values[0] == 0 else f"-0x0F answered {values[0]}, not 0")
        bad = [v for v in values[self.fields] if not math.isfinite(v) or abs(v) > MAX_FIELD_UT]
        return Verdict(f"magnetometer value {bad[0]} outside +-{MAX_FIELD_UT}" if bad else None)

    def apply(self, request: Request, values: Sequence[float], now_ms: int, now_s: float) -> None:
        if request.command is Command.MAGNETOMETER_ENABLE:
            self._switch_on = False
        else:
            super().apply(request, values, now_ms, now_s)

    def reset(self) -> None:
        super().reset()
        self._switch_on = self.enabled  # a restarted firmware has it off again

    @property
    def values(self) -> tuple[float, float, float]:
        """x, y, z in µT."""
        x, y, z = self.packet_values
        return (x, y, z)
