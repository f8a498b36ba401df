"""The three-axis accelerometer, raw (wire command a) or spherical (wire command A).

docs/protocol.md, quirks "a" and "A": ``a`` gives the ADC counts (0 g near 2000, about
800 a g; an e-puck rev 1.3 over Bluetooth gives 0 g at 2048 and about 750 a g). ``A``
gives three floats computed on the dsPIC from the counts less the offsets it measured at
start-up: the magnitude in counts, the orientation and the inclination in degrees, both
converted with 180/3.1415, so they overshoot their ranges by up to 0.006 %. A stock
firmware in Overo mode answers zeros on a rev 1.3 e-puck, whose accelerometer is on I2C:
all zeros cannot be a reading of the analog accelerometer, so they are refused. There,
where the robot's I2C bus is reachable and its LSM330 answers, raw mode reads the chip
over I2C instead (ego.i2c), in the firmware's own 12-bit scaling: 0 g at 2048, 768
counts a g (docs/protocol.md, "The Overo's own I2C bus").
"""

from __future__ import annotations

import enum
import math
from collections.abc import Iterable, Sequence
from typing import ClassVar, NamedTuple

from ego.devices.base import Sensor, Verdict, out_of_range
from ego.devices.table import TABLE, Series
from ego.seam.batch import Request
from ego.seam.profile import Command, Profile

__all__ = [
    "ACC_COUNTS_PER_G",
    "ACC_ZERO_COUNTS",
    "ANGLE_OVERSHOOT",
    "Accelerometer",
    "AccelerometerMode",
    "Spherical",
    "counts_to_mps2",
]

ACC_ZERO_COUNTS = 2000
ACC_COUNTS_PER_G = 800
GRAVITY_MPS2 = 9.81
#: The firmware's degrees per radian, 180/3.1415 (docs/protocol.md, "A").
FIRMWARE_DEGREES_PER_RADIAN = 180 / 3.1415
#: How far past 0..180 and 0..360 that makes the angles reach.
ANGLE_OVERSHOOT = 360 * (FIRMWARE_DEGREES_PER_RADIAN / (180 / math.pi) - 1) + 1e-4
#: What says "this robot's firmware has no accelerometer data for us".
NO_DATA_WHY = (
    "the accelerometer answered all zeros, which the stock firmware in Overo mode sends "
    "for an e-puck rev 1.3 (its accelerometer is an LSM330 on I2C, which the Overo owns)"
)


def counts_to_mps2(
    counts: Sequence[float], zero_counts: float, counts_per_g: float
) -> tuple[float, float, float]:
    """Raw x, y, z counts in m/s^2 with Webots' conversion (docs/protocol.md, "a"): x is
    negated. The one place the counts become an acceleration (the family and a served
    robot's dashboard both use it)."""
    x, y, z = counts
    k = GRAVITY_MPS2 / counts_per_g
    return (-k * (x - zero_counts), k * (y - zero_counts), k * (z - zero_counts))


class AccelerometerMode(str, enum.Enum):
    RAW = "raw"
    SPHERICAL = "spherical"


class Spherical(NamedTuple):
    """The firmware's spherical acceleration, in its own units (docs/protocol.md, "A").

    ``magnitude`` is in accelerometer counts (768 at rest: e_acc.h GRAVITY); the angles are in the
    firmware's degrees, 0..360 and 0..180 give or take :data:`ANGLE_OVERSHOOT`.
    """

    magnitude: float
    orientation_deg: float
    inclination_deg: float


@TABLE.declare(
    "accelerometer",
    webots_rank=3,
    series=Series("accelerometer", "m/s²", ("x", "y", "z")),
)
class Accelerometer(Sensor):
    """Raw 12-bit counts (0 g near 2000, about 800 counts a g) and Webots' m/s^2.

    >>> robot.accelerometer.enable(64)                   # doctest: +SKIP
    >>> robot.step(64); ax, ay, az = robot.accelerometer.acceleration_mps2
    """

    family = "accelerometer"
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

    def validate(self, request: Request, values: Sequence[float], now_s: float) -> Verdict:
        if request.command is Command.ACCELEROMETER_RAW:
            return Verdict(out_of_range("accelerometer", values, 0, 4095))
        magnitude, orientation, inclination = values
        if not math.isfinite(magnitude) or magnitude < 0:
            return Verdict(f"accelerometer magnitude {magnitude} is not finite and non-negative")
        over = ANGLE_OVERSHOOT
        return Verdict(
            out_of_range("accelerometer orientation", [orientation], -over, 360 + over)
            or out_of_range("accelerometer inclination", [inclination], -over / 2, 180 + over / 2)
        )

    def take(self, values: Sequence[float]) -> None:
        if not any(values):
            raise self.missing(NO_DATA_WHY + self.i2c_hint())
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
        """x, y, z in m/s^2 with Webots' conversion (docs/protocol.md, "a"): x is negated.

        0 g and the counts per g are the connected firmware's figures for this robot, or
        the LSM330's when it is read over I2C.
        """
        counts = self.values
        chip = self._via  # the chip last read, even once disabled
        zero, per_g = (
            chip.acc_scale
            if chip is not None and chip.acc_scale is not None
            else (self.profile.acc_zero_counts, self.profile.acc_counts_per_g)
        )
        return counts_to_mps2(counts, zero, per_g)

    def readings(self) -> list[float] | None:
        """The acceleration in m/s^2; None before a sample, or in spherical mode (no vector)."""
        if not self.has_values or self.mode is not AccelerometerMode.RAW:
            return None
        return list(self.acceleration_mps2)

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
