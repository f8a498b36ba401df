"""The three floor (ground) sensors gs0..gs2, left, centre, right (wire command M)."""

from __future__ import annotations

from typing import ClassVar

from ego.devices.base import ArraySensor
from ego.serial.protocol import Command

__all__ = ["FloorSensors"]


class FloorSensors(ArraySensor):
    """IR reflection of the floor, 0..4095: high on white, low on black.

    The stock Overo firmware does not serve them (``M`` answers nothing; they sit on the
    Overo's I2C bus at 0x60), so enabling them there raises UnsupportedDeviceError.

    >>> robot.floor.enable(32)                           # doctest: +SKIP
    >>> robot.step(32); on_line = robot.floor.value("gs1") < 500
    """

    family = "floor sensors"
    names: ClassVar[tuple[str, ...]] = ("gs0", "gs1", "gs2")
    command = Command.FLOOR
