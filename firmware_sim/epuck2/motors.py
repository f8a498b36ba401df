"""The e-puck2's stepper motors: the speed clamp, the stepping rate, the 16-bit casts.

MAIN:src/motors.c:298-335 (motor_set_speed): a speed is clamped to +-MOTOR_SPEED_LIMIT
(1100 steps/s, MAIN:src/motors.h:7), doubled (the driver counts microsteps), and the
motor's timer (100 kHz, motors.c:7) then fires every ``100000 // (2 * |v|)`` ticks, one
microstep a tick; the step counter is the microstep count halved (motors.c:210-224).
The asercom layer hands speeds through ``e_set_speed_left(int)``, which casts to int16
(MAIN:src/epuck1x/motor_led/advance_one_timer/e_motors.c:81-98).
"""

from __future__ import annotations

import math

from firmware_sim.world import World

__all__ = ["MOTOR_SPEED_LIMIT", "fit_world", "int16", "stepping_rate", "uint16"]

#: MAIN:src/motors.h:7, ``MOTOR_SPEED_LIMIT 1100 // [step/s]``.
MOTOR_SPEED_LIMIT = 1100
#: MAIN:src/motors.c:7, ``MOTOR_TIMER_FREQ 100000 // [Hz]``.
MOTOR_TIMER_HZ = 100_000


def int16(value: int) -> int:
    """C's ``(int16_t)value``: the low 16 bits, signed."""
    return ((int(value) + 0x8000) & 0xFFFF) - 0x8000


def uint16(value: int) -> int:
    """The low 16 bits, unsigned (what ``x & 0xff, x >> 8`` puts on the wire)."""
    return int(value) & 0xFFFF


def clamp_speed(speed_steps: int) -> int:
    """motors.c:300-305: the commanded speed, clamped to +-1100 steps/s."""
    return max(-MOTOR_SPEED_LIMIT, min(MOTOR_SPEED_LIMIT, int(speed_steps)))


def stepping_rate(speed_steps: int) -> float:
    """Steps a second a wheel really makes for a commanded speed (motors.c:309-334).

    The timer period is ``100000 // (2 v)`` ticks (a uint16), one microstep a period,
    two microsteps a step: 600 steps/s really runs at 602.4.
    """
    v = clamp_speed(speed_steps)
    if v == 0:
        return 0.0
    interval = MOTOR_TIMER_HZ // (2 * abs(v))
    return math.copysign(MOTOR_TIMER_HZ / interval / 2, v)


def fit_world(world: World) -> None:
    """Give a firmware_sim World the e-puck2's motor driver (clamp and stepping rate)."""
    world.max_speed_steps = MOTOR_SPEED_LIMIT
    world.motor_rate = stepping_rate
