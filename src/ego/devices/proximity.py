"""The eight infra-red proximity sensors ps0..ps7, plus the Overo board's ps8/ps9 (wire N)."""

from __future__ import annotations

from collections.abc import Callable
from typing import ClassVar

from ego.devices.base import ArraySensor
from ego.devices.table import RAW, TABLE, Series
from ego.errors import EgoError
from ego.seam.profile import Command, Profile

__all__ = ["ProximitySensors"]


@TABLE.declare(
    "proximity",
    webots_rank=4,
    series=Series("proximity", RAW, (*(f"ps{i}" for i in range(8)), "IR8", "IR9")),
)
class ProximitySensors(ArraySensor):
    """IR proximity, 0..~4095, higher is closer; parsed signed (it can dip below 0).

    >>> robot.proximity.enable(64)                       # doctest: +SKIP
    >>> robot.step(64)
    >>> front = max(robot.proximity.value("ps0"), robot.proximity.value("ps7"))
    """

    family = "proximity sensors"
    command = Command.PROXIMITY
    #: Calibrated IR can dip below 0 (docs/protocol.md: parse signed); far below is corruption.
    value_range: ClassVar[tuple[int, int]] = (-1024, 4095)

    def __init__(self, profile: Profile) -> None:
        super().__init__(profile)
        self._calibrate: Callable[[], None] | None = None

    @property
    def member_names(self) -> tuple[str, ...]:
        # docs/protocol.md: the stock firmware in Overo mode adds the Overo board's
        # long-range IR8 (left) and IR9 (right) to N's reply.
        return self.names[: self.profile.reply_values(Command.PROXIMITY) or 8]

    def bind_calibration(self, calibrate: Callable[[], None]) -> None:
        """The robot's way of sending ``K`` (this family does no I/O itself)."""
        self._calibrate = calibrate

    def calibrate(self) -> None:
        """Calibrate the sensors' zero against the current surroundings (ASCII ``K``).

        Keep every object out of the sensors' range: the dsPIC averages what they see
        now and subtracts it from later readings (the stock firmware; Webots' firmware
        calibrates too but keeps answering raw values). It takes about 1 s (stock) or
        1.5 s (Webots), during which the dsPIC does not listen to the line.
        """
        if self._calibrate is None:
            raise EgoError("these proximity sensors are not attached to a robot")
        self._calibrate()
