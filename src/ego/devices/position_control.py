"""Driving a wheel to an angle, as Webots' position control does: sans-I/O, one function.

Webots' ``Motor.setPosition(angle)`` turns the wheel there at the set velocity. The
e-puck's steppers take speeds only, so after each step the Webots face asks
:func:`position_speed` for the speed that brings the wheel (as its step counter says)
towards the target, and sends it.
"""

from __future__ import annotations

import math

from ego.devices.motors import rad_s_to_steps
from ego.serial.profiles import STEPS_PER_TURN

__all__ = ["GAIN_PER_S", "TOLERANCE_RAD", "position_speed", "position_speed_rad_s"]

#: Within this of the target the wheel stops: one step of the stepper.
TOLERANCE_RAD = 2 * math.pi / STEPS_PER_TURN
#: Near the target the speed is proportional to the distance left: rad/s per rad.
GAIN_PER_S = 5.0


def position_speed_rad_s(target_rad: float, current_rad: float, max_velocity_rad_s: float) -> float:
    """The wheel speed (rad/s) towards ``target_rad`` from ``current_rad``.

    Full ``max_velocity_rad_s`` (its sign ignored) far away, proportional to the distance
    near it, 0 within one step of it.
    """
    error = target_rad - current_rad
    if abs(error) < TOLERANCE_RAD:
        return 0.0
    speed = min(abs(max_velocity_rad_s), GAIN_PER_S * abs(error))
    return math.copysign(speed, error)


def position_speed(target_rad: float, current_rad: float, max_velocity_rad_s: float) -> int:
    """:func:`position_speed_rad_s` in whole steps/s, the unit the motors take."""
    return round(rad_s_to_steps(position_speed_rad_s(target_rad, current_rad, max_velocity_rad_s)))
