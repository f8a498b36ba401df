"""The e-puck2's main processor peripherals over a firmware_sim World: what the asercom
code calls (motors, LEDs, sound, sensors), with the ground truth tests compare against."""

from __future__ import annotations

import threading
from collections import deque
from dataclasses import dataclass

import numpy as np

from firmware_sim.epuck2.imu import Imu
from firmware_sim.epuck2.leds import Leds
from firmware_sim.epuck2.motors import fit_world, int16
from firmware_sim.epuck2.sensors import (
    Battery,
    GroundModule,
    Microphones,
    Proximity,
    TimeOfFlight,
)
from firmware_sim.world import World

__all__ = ["SOUNDS", "Epuck2Robot", "SoundEvent"]

#: Asercom2.c:553-571 (the -0x09 sound bits) and 1492-1507 (ASCII T,1..5).
SOUNDS = {
    1: "mario",  # playMelody(MARIO, ML_FORCE_CHANGE)
    2: "underworld",  # playMelody(UNDERWORLD, ...)
    3: "starwars",  # playMelody(STARWARS, ...)
    4: "sample 7294,3732",  # e_play_sound(7294, 3732)
    5: "sample 11028,8016",  # e_play_sound(11028, 8016)
}
#: A wide seed stream of this package's own, apart from the world's noise.
_STREAM = 0x65707532


@dataclass(frozen=True, slots=True)
class SoundEvent:
    """A sound started (or ``stop``) at world time ``t_s``; a started melody restarts."""

    t_s: float
    name: str


class Epuck2Robot:
    """One e-puck2 in ``world``: selector, button, SD card, ground module, battery."""

    def __init__(
        self,
        world: World,
        *,
        seed: int | None = None,
        selector: int = 8,
        ground_module: bool = False,
        sd_card: bool = False,
        battery_v: float = 3.9,
        temperature_c: float = 30.0,
    ) -> None:
        if not 0 <= selector <= 15:
            raise ValueError(f"selector {selector} is not one of 0..15")
        self.world = world
        fit_world(world)  # the 1100 steps/s clamp and the e-puck2's stepping rate
        rng = np.random.default_rng(None if seed is None else [seed, _STREAM])
        self.selector = selector
        self.button = False
        self.sd_card = sd_card
        #: The TV remote's last RC5 frame: toggle/check, address, data (none received).
        self.rc5 = (0, 0, 0)
        self.leds = Leds(world)
        self.imu = Imu(world, rng, temperature_c)
        self.proximity = Proximity(world)
        self.tof = TimeOfFlight(world, rng)
        self.microphones = Microphones(world, rng)
        self.ground = GroundModule(world, ground_module)
        self.battery = Battery(battery_v)
        #: behaviors.c's obstacle avoidance, switched by the -0x09 settings bit 1 (its
        #: steering of the wheels is not modelled).
        self.obstacle_avoidance = False
        self._sounds: deque[SoundEvent] = deque(maxlen=10_000)
        self._sounds_lock = threading.Lock()

    # -- motors (MAIN:src/epuck1x/motor_led/advance_one_timer/e_motors.c) ---------------

    def set_speeds(self, left: int, right: int) -> None:
        """e_set_speed_left/right: cast to int16 (e_motors.c:83, 97), clamped by the
        motor driver to +-1100 (the world holds the clamp, motors.fit_world)."""
        self.world.set_speeds(int16(left), int16(right))

    def set_steps(self, left: int, right: int) -> None:
        """e_set_steps_left/right -> left_motor_set_pos: the counter becomes ``value``
        (MAIN:src/motors.c:218-224, counted in microsteps, two a step)."""
        self.world.set_steps(int(left), int(right))

    def steps(self) -> tuple[int, int]:
        """e_get_steps_left/right: the microstep count halved, as int32 (motors.c:210-216)."""
        counts = self.world.step_counts()
        return tuple(int(int(s * 2) / 2) for s in counts)  # type: ignore[return-value]

    # -- sound ------------------------------------------------------------------------

    def play(self, number: int) -> None:
        """Start sound ``number`` of :data:`SOUNDS` (a melody restarts: ML_FORCE_CHANGE)."""
        with self._sounds_lock:
            self._sounds.append(SoundEvent(self.world.clock(), SOUNDS[number]))

    def stop_sound(self) -> None:
        """e_close_sound(); stopCurrentMelody()."""
        with self._sounds_lock:
            self._sounds.append(SoundEvent(self.world.clock(), "stop"))

    def sounds(self) -> list[SoundEvent]:
        """Sounds started and stopped, oldest first (ground truth; the last 10,000)."""
        with self._sounds_lock:
            return list(self._sounds)

    def sound_names(self) -> list[str]:
        return [event.name for event in self.sounds()]
