"""How the emulated e-puck's wheels meet the floor: slip, and noise in the step counters.

A real e-puck's odometry drifts: its tyres slip a little on the floor, and no two wheels
are quite alike, so the ground a wheel covers falls short of what its turning says, by
a different fraction on each side (a slow heading drift follows). Its step counters are
also read through a noisy estimate here, for controllers to be tried against it. Both
are small by default (about 1 % slip, a step of counter noise a wheel turn), so that a
short odometry run still lands within a centimetre of the truth while a long one drifts
visibly. ``WheelModel(slip=0, encoder_noise_steps=0)`` gives the ideal wheels.

The draws come from a generator of their own, seeded from the world's seed, so that the
sensors' noise is the same with or without the model.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["MAX_ENCODER_NOISE_STEPS", "MAX_SLIP", "WheelModel", "Wheels"]

#: The largest slip fraction a world may ask for (half the turning lost).
MAX_SLIP = 0.5
#: The largest counter noise a world may ask for (steps, over one wheel turn).
MAX_ENCODER_NOISE_STEPS = 100.0
#: A wheel turn in steps (e_motors.c: 1000 steps a turn).
_TURN_STEPS = 1000.0
#: How much two wheels' slip may differ: each is the mean give or take this fraction of it.
_SPREAD = 0.5
#: Mixed into the world's seed so that the wheels draw apart from the sensors' noise.
_STREAM = 0x77686565


@dataclass(frozen=True, slots=True)
class WheelModel:
    """Slip and counter noise of a world's wheels.

    ``slip``: the mean fraction (0..0.5) of its turning that each wheel loses to slip
    on the floor; each wheel gets its own, within half of it either way. ``encoder_noise_steps``:
    the standard deviation (0..100 steps) of a step counter's error after one wheel turn
    (a random walk: it grows with the square root of the distance turned).
    """

    slip: float = 0.01
    encoder_noise_steps: float = 1.0

    def __post_init__(self) -> None:
        for name, value, high in (
            ("slip", self.slip, MAX_SLIP),
            ("encoder_noise_steps", self.encoder_noise_steps, MAX_ENCODER_NOISE_STEPS),
        ):
            if isinstance(value, bool) or not isinstance(value, int | float):
                raise ValueError(f"wheel {name} {value!r} is not a number")
            if not (math.isfinite(value) and 0.0 <= value <= high):
                raise ValueError(f"wheel {name} {value!r} is outside 0..{high:g}")

    @property
    def ideal(self) -> bool:
        return self.slip == 0 and self.encoder_noise_steps == 0


class Wheels:
    """One robot's pair of wheels under a :class:`WheelModel` (not thread-safe: the world
    calls it under its lock)."""

    def __init__(self, model: WheelModel | None = None, seed: int | None = None) -> None:
        self.model = model if model is not None else WheelModel()
        self._rng = np.random.default_rng(None if seed is None else [seed, _STREAM])
        draws = 1.0 + _SPREAD * self._rng.uniform(-1.0, 1.0, size=2)
        #: Each wheel's own slip fraction (left, right).
        self.slip = (float(self.model.slip * draws[0]), float(self.model.slip * draws[1]))

    def ground(self, left_steps: float, right_steps: float) -> tuple[float, float]:
        """What the wheels' turning (steps) covers on the floor, in steps of travel."""
        return left_steps * (1.0 - self.slip[0]), right_steps * (1.0 - self.slip[1])

    def counted(self, turned_steps: float, noisy: bool = True) -> float:
        """What a step counter adds for ``turned_steps`` of turning: the turning, give or
        take the counter's noise, never of the other sign (a counter does not run back)."""
        sigma = self.model.encoder_noise_steps
        if not noisy or sigma == 0 or turned_steps == 0:
            return turned_steps
        error = float(self._rng.normal(0.0, sigma * math.sqrt(abs(turned_steps) / _TURN_STEPS)))
        counted = turned_steps + error
        return counted if counted * turned_steps > 0 else 0.0
