"""Webots' ``PositionSensor``: a wheel's step counter as an angle."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from ego.controller.device import NAN as _NAN
from ego.controller.device import Device, _sibling, view
from ego.controller.sensor import Sensor
from ego.devices.table import spec

if TYPE_CHECKING:
    from ego.core.robot import Robot as CoreRobot

__all__ = ["PositionSensor", "encoder_steps", "whole_steps"]


def whole_steps(value: float) -> int:
    """A finite float rounded to whole steps (the C API passes doubles); anything else as
    it is, so that the core refuses it with its own typed error (NaN, a string...)."""
    if isinstance(value, float) and math.isfinite(value):
        return round(value)
    return value  # type: ignore[return-value]  # not an int: the core's check refuses it


def encoder_steps(core: CoreRobot, side: int) -> float:
    """A wheel's step count, NaN unless the encoders are enabled and sampled."""
    encoders = core.encoders
    return float(encoders.values[side]) if encoders.enabled and encoders.has_values else _NAN


@view("PositionSensor")
class PositionSensor(Sensor):
    """A wheel's step counter as an angle in radians."""

    ROTATIONAL = 0
    LINEAR = 1

    def getType(self) -> int:
        return self.ROTATIONAL

    def getMotor(self) -> Device | None:
        """The wheel's motor (``left wheel sensor`` -> ``left wheel motor``)."""
        return _sibling(self, self._name.replace("sensor", "motor"))

    def getBrake(self) -> None:
        """None: the e-puck's wheels have no brake device."""
        return None

    def getValue(self) -> float:
        if not self._readable():
            return _NAN
        return self._core.encoders.radians[spec(self._name).index]

    value = property(lambda self: self.getValue())
    type = property(lambda self: self.getType())
    motor = property(lambda self: self.getMotor())
    brake = property(lambda self: self.getBrake())
