"""The three floor (ground) sensors gs0..gs2, left, centre, right (wire command M)."""

from __future__ import annotations

from collections.abc import Sequence

from ego.devices.base import FINE, ArraySensor, Verdict
from ego.devices.table import RAW, TABLE, Series
from ego.seam.batch import Request
from ego.seam.profile import Command

__all__ = ["FloorSensors"]


@TABLE.declare("floor", webots_rank=5, series=Series("floor", RAW, ("gs0", "gs1", "gs2")))
class FloorSensors(ArraySensor):
    """IR reflection of the floor, 0..4095: high on white, low on black.

    The stock firmware in Overo mode does not serve them (``M`` answers nothing): it
    leaves the I2C bus to the Overo, which reads the ground module at 0x60 itself
    (ego.i2c; docs/protocol.md, "The Overo's own I2C bus"). Where that bus is out of
    reach or the module does not answer on it, enabling them raises
    UnsupportedDeviceError naming the way out. Over Bluetooth the stock firmware adds two
    cliff sensors to ``M``'s reply (ignored here). Without the ground module fitted, the
    firmware's I2C reads go unacknowledged and every byte reads 0xFF (docs/protocol.md,
    "M"): that raises UnsupportedDeviceError too.

    >>> robot.floor.enable(32)                           # doctest: +SKIP
    >>> robot.step(32); on_line = robot.floor.value("gs1") < 500
    """

    family = "floor sensors"
    command = Command.FLOOR
    #: What an unacknowledged I2C read gives.
    NO_MODULE = 0xFFFF

    def validate(self, request: Request, values: Sequence[float], now_s: float) -> Verdict:
        if all(v == self.NO_MODULE for v in values):
            return FINE  # not a corruption: take() says what it means
        return super().validate(request, values, now_s)

    def take(self, values: Sequence[float]) -> None:
        if all(v == self.NO_MODULE for v in values):
            raise self.missing(
                "every ground sensor reads 0xFFFF, as when the ground module is not fitted "
                "(the firmware reads it over I2C without checking the acknowledge)"
            )
        super().take(values)
