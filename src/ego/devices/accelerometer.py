"""The three-axis accelerometer, raw (wire command a) or spherical (wire command A)."""

from __future__ import annotations

import enum
import math
from collections.abc import Iterable, Sequence
from typing import ClassVar, NamedTuple

from ego.devices.base import Sensor, out_of_range
from ego.serial.protocol import Command, Profile, Request

__all__ = ["ACC_COUNTS_PER_G", "ACC_ZERO_COUNTS", "Accelerometer", "AccelerometerMode", "Spherical"]

ACC_ZERO_COUNTS = 2000
ACC_COUNTS_PER_G = 800
GRAVITY_MPS2 = 9.81


class AccelerometerMode(str, enum.Enum):
    RAW = "raw"
    SPHERICAL = "spherical"


class Spherical(NamedTuple):
    """Spherical acceleration: magnitude (g), orientation 0-360 deg, inclination 0-180 deg."""

    magnitude: float
    orientation_deg: float
    inclination_deg: float


class Accelerometer(Sensor):
    """Raw 12-bit counts (0 g near 2000, about 800 counts a g) and Webots' m/s^2.

    >>> robot.accelerometer.enable(64)                   # doctest: +SKIP
    >>> robot.step(64); ax, ay, az = robot.accelerometer.acceleration_mps2
    """

    family = "accelerometer"
    names: ClassVar[tuple[str, ...]] = ("accelerometer",)
    command = Command.ACCELEROMETER_RAW
    _commands: ClassVar[dict[AccelerometerMode, Command]] = {
        AccelerometerMode.RAW: Command.ACCELEROMETER_RAW,
        AccelerometerMode.SPHERICAL: Command.ACCELEROMETER_SPHERICAL,
    }

    def __init__(self, profile: Profile) -> None:
        super().__init__(profile)
        self.mode = AccelerometerMode.RAW
        self._raw: tuple[int, int, int] = (0, 0, 0)
        self._spherical = Spherical(0.0, 0.0, 0.0)

    def enable(
        self,
        period_ms: int,
        names: Iterable[str] | None = None,
        mode: AccelerometerMode | str = AccelerometerMode.RAW,
    ) -> None:
        """Sample every ``period_ms`` in ``mode`` ("raw" or "spherical")."""
        try:
            chosen = AccelerometerMode(mode)
        except ValueError:
            from ego.errors import OutOfRangeError

            raise OutOfRangeError(
                f"accelerometer mode {mode!r} is not one of 'raw', 'spherical'"
            ) from None
        previous, self.mode = self.mode, chosen
        try:
            super().enable(period_ms, names)
        except Exception:
            self.mode = previous
            raise

    def command_for_enable(self) -> Command:
        return self._commands[self.mode]

    def current_command(self) -> Command:
        return self._commands[self.mode]

    def check(self, request: Request, values: Sequence[float], now_s: float) -> str | None:
        if request.command is Command.ACCELEROMETER_RAW:
            return out_of_range("accelerometer", values, 0, 4095)
        magnitude, orientation, inclination = values
        if not math.isfinite(magnitude) or magnitude < 0:
            return f"accelerometer magnitude {magnitude} is not a finite non-negative number"
        return out_of_range("accelerometer orientation", [orientation], 0.0, 360.0) or (
            out_of_range("accelerometer inclination", [inclination], 0.0, 180.0)
        )

    def take(self, values: Sequence[float]) -> None:
        if self.mode is AccelerometerMode.RAW:
            x, y, z = (int(v) for v in values)
            self._raw = (x, y, z)
        else:
            self._spherical = Spherical(*(float(v) for v in values))

    @property
    def values(self) -> tuple[int, int, int]:
        """Raw x, y, z counts of the last sample (raw mode)."""
        self._require_mode(AccelerometerMode.RAW)
        return self._raw

    @property
    def acceleration_mps2(self) -> tuple[float, float, float]:
        """x, y, z in m/s^2 with Webots' conversion (protocol.md): x is negated."""
        x, y, z = self.values
        k = GRAVITY_MPS2 / ACC_COUNTS_PER_G
        return (-k * (x - ACC_ZERO_COUNTS), k * (y - ACC_ZERO_COUNTS), k * (z - ACC_ZERO_COUNTS))

    @property
    def spherical(self) -> Spherical:
        """Magnitude, orientation and inclination of the last sample (spherical mode)."""
        self._require_mode(AccelerometerMode.SPHERICAL)
        return self._spherical

    def _require_mode(self, mode: AccelerometerMode) -> None:
        self.require_values()
        if self.mode is not mode:
            from ego.errors import DeviceError

            raise DeviceError(
                f"the accelerometer samples in {self.mode.value} mode; "
                f"enable it with mode={mode.value!r} to read that"
            )
