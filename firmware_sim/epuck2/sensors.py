"""The e-puck2's other sensors from the world: IR proximity and ambient light, the
time-of-flight distance sensor, four microphones, the ground module, the battery.

Each is written from the main processor's driver (cited per item); where the firmware
only passes a chip's number through, the number comes from firmware_sim's world.
"""

from __future__ import annotations

import math

import numpy as np

from firmware_sim.world import ROBOT_RADIUS_M, World

__all__ = ["Battery", "GroundModule", "Microphones", "Proximity", "TimeOfFlight"]


class Proximity:
    """IR proximity and ambient light (MAIN:src/sensors/proximity.c).

    ``get_calibrated_prox`` is the reflected value less the value calibrate_ir measured
    (100 samples, proximity.c:210-228), never below 0 (proximity.c:385-397); the robot
    calibrates at power-on (MAIN:src/main.c:133), in its start pose. Ambient light is
    passed through (proximity.c:399-405): lower is brighter. Sampling can be stopped
    (binary -0x10 with 0, Asercom2.c:685): the last values then stay.
    """

    def __init__(self, world: World) -> None:
        self.world = world
        self._init_value = [0] * 8
        self.sampling = True
        self._last: tuple[list[int], list[int]] = ([0] * 8, [0] * 8)
        self.calibrate()

    def calibrate(self) -> None:
        """calibrate_ir: remember what the sensors see now as their zero."""
        self._init_value = self.world.proximity()

    def forget_calibration(self) -> None:
        """Zero offsets, as in firmware that does not calibrate at power-on (the
        ``gumstix`` branch's main(), e-puck2_main-processor@517ef07:src/main.c:378-430)."""
        self._init_value = [0] * 8

    def _sample(self) -> tuple[list[int], list[int]]:
        if self.sampling:
            delta = self.world.proximity()
            calibrated = [max(0, d - z) for d, z in zip(delta, self._init_value, strict=True)]
            self._last = (calibrated, self.world.light())
        return self._last

    def calibrated(self) -> list[int]:
        return self._sample()[0]

    def sample(self) -> tuple[list[int], list[int]]:
        """Calibrated proximity and ambient light from one sampling of the world."""
        calibrated, ambient = self._sample()
        return list(calibrated), list(ambient)

    def ambient(self) -> list[int]:
        return self._sample()[1]


class TimeOfFlight:
    """The VL53L0X at the front (MAIN:src/sensors/VL53L0X/VL53L0X.c).

    Long-range mode (VL53L0X.c:153-176: 0.1 MCPS signal limit, 60 mm sigma, 33 ms
    budget), read by a thread every 100 ms (VL53L0X.c:45-52), so the value holds between
    reads; VL53L0X_get_dist_mm returns the last one (VL53L0X.c:252-254). Stopping the
    thread (-0x11 with 0) freezes it. Beyond the long-range mode's 2 m the chip reports
    its "no target" range, 8190 mm [inferred from the VL53L0X's behaviour; the firmware
    passes RangeMilliMeter through whatever the status, vl53l0x_api.c:2486-2493].
    """

    PERIOD_S = 0.1
    MAX_RANGE_MM = 2000
    OUT_OF_RANGE_MM = 8190

    def __init__(self, world: World, rng: np.random.Generator) -> None:
        self.world = world
        self._rng = rng
        self.running = True
        self._value = 0  # dist_mm is 0 until the first read (VL53L0X.c:17)
        self._read_at = -math.inf

    def measure_mm(self) -> int:
        """A fresh reading: the ray from the sensor, straight ahead, to the first face."""
        pose = self.world.snapshot()
        ox = pose.x_m + ROBOT_RADIUS_M * math.cos(pose.theta_rad)
        oy = pose.y_m + ROBOT_RADIUS_M * math.sin(pose.theta_rad)
        mm = self.world.ray_distance(ox, oy, pose.theta_rad) * 1000.0
        if self.world.noise:
            mm += float(self._rng.normal(0.0, 3.0))
        if mm > self.MAX_RANGE_MM:
            return self.OUT_OF_RANGE_MM
        return max(0, int(round(mm)))

    def distance_mm(self) -> int:
        if self.running:
            now = self.world.clock()
            if now - self._read_at >= self.PERIOD_S:
                self._value = self.measure_mm()
                self._read_at = now
        return self._value


#: MAIN:src/audio/microphone.h:28-31: mic0 right, mic1 left, mic2 back, mic3 front;
#: offsets (forward, left) in metres on the e-puck2's board [positions inferred].
MIC_OFFSETS_M = ((0.0, -0.03), (0.0, 0.03), (-0.03, 0.0), (0.03, 0.0))


class Microphones:
    """Volumes of the four microphones (MAIN:src/audio/microphone.c:32-73): max - min of
    the last block of 16-bit samples, shifted right by 4 for the e-puck1's 12-bit scale
    (MAIN:src/epuck1x/a_d/advance_ad_scan/e_micro.c:35-39). The world's sound source
    gives the level: its amplitude (ADC counts at 10 cm) falling with distance."""

    def __init__(self, world: World, rng: np.random.Generator) -> None:
        self.world = world
        self._rng = rng

    def volumes(self) -> list[int]:
        pose = self.world.snapshot()
        c, s = math.cos(pose.theta_rad), math.sin(pose.theta_rad)
        sound = self.world.sound
        out = []
        for forward, left in MIC_OFFSETS_M:
            mx, my = pose.x_m + forward * c - left * s, pose.y_m + forward * s + left * c
            d = math.hypot(sound.x_m - mx, sound.y_m - my)
            peak_to_peak = 2.0 * sound.amplitude / (1.0 + d / 0.1)
            if self.world.noise:
                peak_to_peak += abs(float(self._rng.normal(0.0, 3.0)))
            out.append(max(0, min(0xFFFF, int(peak_to_peak))))
        return out


class GroundModule:
    """The optional ground-sensor board at I2C 0x60 (MAIN:src/sensors/ground.c).

    ground_start reads 21 registers once; if nothing answers it gives up and every value
    stays 0 (ground.c:66-86). Fitted, it gives 3 ground and 2 cliff "delta" values and
    their ambient ones (ground.c:88-99). The three ground values come from the world's
    floor; the cliff sensors and the ambient values are stand-ins [inferred: a flat
    floor, a dim room].
    """

    AMBIENT = 1000

    def __init__(self, world: World, fitted: bool) -> None:
        self.world = world
        self.fitted = fitted

    def delta(self) -> list[int]:
        """get_ground_prox(0..4): 3 ground, 2 cliff."""
        if not self.fitted:
            return [0] * 5
        return [*self.world.floor(), 0, 0]

    def ambient(self) -> list[int]:
        """get_ground_ambient_light(0..4)."""
        return [self.AMBIENT] * 5 if self.fitted else [0] * 5


class Battery:
    """The battery ADC (MAIN:src/sensors/battery_level.c and .h).

    raw = volts * 4096 * R2/(R1+R2) / VREF with R1 220 k, R2 330 k, VREF 3.0 V
    (battery_level.h:14-15, battery_level.c:15-20); percentage (3.4..4.2 V -> 0..100,
    battery_level.c:102-105) truncated to unsigned (utility.c:29-31).
    """

    def __init__(self, volts: float = 3.9) -> None:
        self.volts = volts

    def raw(self) -> int:
        return int(self.volts * 4096 * (330 / 550) / 3.0) & 0xFFFF

    def percentage(self) -> int:
        return max(0, int((self.volts - 3.4) * 100 / (4.2 - 3.4)))
