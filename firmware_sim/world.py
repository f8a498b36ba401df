"""A small world for the emulated e-puck: a walled arena, a lamp, a sound source, a floor pattern.

Values move the way a real robot's do: the step counters integrate the wheel speeds (the
wheels slip a little, and the counters are a little noisy: firmware_sim.wheels),
proximity follows the e-puck IR response to the nearest surface, light falls (lower is
brighter) as the lamp gets nearer, the accelerometer sees gravity and motion, and the
microphones hear the source. Time is the host's monotonic clock, so a controller that
drives for one second moves the robot one second's worth.
Frame: x east, y north, theta = 0 faces +x, counter-clockwise positive; the robot's
geometry is firmware_sim.epuck_model's.
"""

from __future__ import annotations

import math
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from firmware_sim.epuck_model import (
    ACC_PER_G,
    ACC_ZERO,
    AXLE_M,
    BATTERY_RAW,
    FLOOR_SENSOR_OFFSETS_M,
    GRAVITY,
    IR_RESPONSE,
    LONG_RANGE_BEARINGS_RAD,
    MAX_SPEED_STEPS,
    METRES_PER_STEP,
    ROBOT_RADIUS_M,
    SENSOR_BEARINGS_RAD,
    microphone_buffers,
    spherical_from_raw,
    stepping_rate,
)
from firmware_sim.floor import ImageFloor, LineTrack, Marks, Plain
from firmware_sim.frame import Frame
from firmware_sim.layout import (
    Arena,
    Block,
    Lamp,
    Pose,
    SoundSource,
    default_blocks,
    ray_box,
    ray_disc,
)
from firmware_sim.markers import Marker
from firmware_sim.wheels import WheelModel, Wheels

Floor = Marks | LineTrack | Plain | ImageFloor

__all__ = [
    "IR_RESPONSE",
    "ROBOT_RADIUS_M",
    "Arena",
    "Block",
    "Lamp",
    "Pose",
    "SoundSource",
    "World",
    "stepping_rate",
]

@dataclass(slots=True)
class _Body:
    x_m: float = 0.0
    y_m: float = 0.0
    theta_rad: float = 0.0
    speed_steps: list[int] = field(default_factory=lambda: [0, 0])
    steps: list[float] = field(default_factory=lambda: [0.0, 0.0])
    forward_mps: float = 0.0
    forward_acc: float = 0.0
    lateral_acc: float = 0.0
    leds: list[int] = field(default_factory=lambda: [0] * 10)


class World:
    """The emulator's ground truth; every method is thread-safe."""

    def __init__(
        self,
        seed: int | None = None,
        arena: Arena | None = None,
        blocks: list[Block] | None = None,
        lamp: Lamp | None = None,
        sound: SoundSource | None = None,
        start: Pose | None = None,
        noise: bool = True,
        floor: Floor | None = None,
        devices: frozenset[str] = frozenset(),
        camera_size: tuple[int, int] | None = None,
        starts: list[Pose] | None = None,
        wheels: WheelModel | None = None,
    ) -> None:
        self.arena = arena or Arena()
        self.floor_pattern = floor or Marks()
        #: Ground-truth devices the world declares ("gps", "compass", "touch sensor").
        self.devices = frozenset(devices)
        #: The camera size the world file sets (Webots' camera_width/height), else None.
        self.camera_size = camera_size
        #: The other robots sharing this world (a swarm: firmware_sim.crowd), else None.
        self.crowd: Any = None
        self.blocks = default_blocks() if blocks is None else list(blocks)
        #: Named solids only a Supervisor sees (firmware_sim.markers): a world file's.
        self.markers: list[Marker] = []
        self.lamp = lamp or Lamp()
        self.sound = sound or SoundSource()
        self.noise = noise
        self._rng = np.random.default_rng(seed)
        #: The wheels' slip and counter noise (firmware_sim.wheels; small by default).
        self.wheels = Wheels(wheels, seed)
        self._lock = threading.RLock()
        self._start = start or Pose(0.0, 0.0, 0.0)
        #: Every robot's start pose the world file gives (a swarm's), this one's first.
        self.starts = list(starts) if starts else [self._start]
        self._body = _Body(self._start.x_m, self._start.y_m, self._start.theta_rad)
        #: The world's time (s): the host's monotonic clock, or a virtual one
        #: (firmware_sim.virtual_time) that only the controller's steps advance.
        self.clock: Callable[[], float] = time.monotonic
        self._t = self.clock()
        #: The robot's DEF name in a world file, if it has one.
        self.robot_name: str | None = None
        #: Where the arena sits in the world file's frame, and the file's convention
        #: (firmware_sim.frame): a Supervisor, a GPS and a Compass answer in that frame.
        self.frame = Frame()
        #: Where each ground-truth device sits on the robot (m, x forward, y left, z up):
        #: a .wbt world's E-puck slots (firmware_sim.wbt_slots); else at its centre.
        self.mounts: dict[str, tuple[float, float, float]] = {}
        #: Every E-puck's DEF name in a world file (a swarm's, in order; None: none given).
        self.robot_names: list[str | None] = []
        #: Every E-puck's emitter and receiver channels in a world file (a swarm's).
        self.robot_radio: list[tuple[int, int]] = []
        #: A world file's bodiless supervisors (firmware_sim.wbt_supervisor.Bodiless).
        self.supervisors: list[Any] = []
        self.battery_raw = BATTERY_RAW
        #: The motor driver: the clamp of a commanded speed (steps/s) and the rate a wheel
        #: then really steps at. The e-puck1's by default; another robot's firmware model
        #: (firmware_sim.epuck2) puts its own here.
        self.max_speed_steps = MAX_SPEED_STEPS
        self.motor_rate: Callable[[int], float] = stepping_rate
        #: Closest distance (m) between the body and any wall or block so far.
        self.closest_approach_m = math.inf
        self.distance_travelled_m = 0.0

    # -- state ---------------------------------------------------------------------

    def reset(self) -> None:
        """What a dsPIC reset does to the robot: motors stop, counters and LEDs clear."""
        with self._lock:
            self.advance()
            self._body.speed_steps = [0, 0]
            self._body.steps = [0.0, 0.0]
            self._body.leds = [0] * 10

    def snapshot(self) -> Pose:
        with self._lock:
            self.advance()
            return Pose(self._body.x_m, self._body.y_m, self._body.theta_rad)

    def start_at(self, pose: Pose) -> None:
        """Make ``pose`` this robot's start (a swarm's robots each have theirs), and go there."""
        self._start = pose
        self.place(pose)

    def place(self, pose: Pose) -> None:
        with self._lock:
            self.advance()
            self._body.theta_rad = pose.theta_rad
            self._body.x_m, self._body.y_m = self._resolve_collisions(pose.x_m, pose.y_m)

    def use_clock(self, clock: Callable[[], float]) -> None:
        """Keep the world's time with ``clock`` from now on (a virtual one, say)."""
        with self._lock:
            self.advance()
            self.clock = clock
            self._t = clock()

    def velocity(self) -> tuple[float, float, float]:
        """The body's velocity now: vx, vy (m/s, world frame) and its turn rate (rad/s)."""
        with self._lock:
            b = self._body
            left, right = (self.motor_rate(v) * METRES_PER_STEP for v in b.speed_steps)
            v = (left + right) / 2
            return v * math.cos(b.theta_rad), v * math.sin(b.theta_rad), (right - left) / AXLE_M

    def move_block(self, index: int, x_m: float, y_m: float, yaw_rad: float) -> None:
        """Put block ``index`` at (x, y), turned ``yaw_rad`` about the vertical."""
        with self._lock:
            self.blocks[index] = replace(self.blocks[index], x_m=x_m, y_m=y_m, yaw_rad=yaw_rad)

    @property
    def speeds(self) -> tuple[int, int]:
        with self._lock:
            return (self._body.speed_steps[0], self._body.speed_steps[1])

    @property
    def leds(self) -> tuple[int, ...]:
        with self._lock:
            return tuple(self._body.leds)

    def set_speeds(self, left: int, right: int) -> None:
        """Commanded wheel speeds; the firmware clamps them to +-max_speed_steps steps/s."""
        with self._lock:
            self.advance()
            self._body.speed_steps = [
                max(-self.max_speed_steps, min(self.max_speed_steps, v)) for v in (left, right)
            ]

    def set_led(self, index: int, value: int) -> None:
        """e_led.c: led 0-7 ring, 8 body, 9 front; any other number sets all ring LEDs.

        A value of 0 switches off, 1 on, anything greater toggles.
        """
        with self._lock:
            targets = [index] if 0 <= index <= 9 else list(range(8))
            for i in targets:
                if value > 1:
                    self._body.leds[i] ^= 1
                else:
                    self._body.leds[i] = 1 if value else 0

    def set_steps(self, left: int, right: int) -> None:
        with self._lock:
            self.advance()
            self._body.steps = [float(left), float(right)]

    def step_counts(self) -> tuple[float, float]:
        """The step counters as turned so far (steps, not wrapped; noisy like the rest)."""
        with self._lock:
            self.advance()
            return (self._body.steps[0], self._body.steps[1])

    def steps_int16(self) -> tuple[int, int]:
        """The step counters as the firmware holds them: int16, wrapping at +-32768."""
        with self._lock:
            self.advance()
            return tuple(  # type: ignore[return-value]
                ((int(math.floor(s)) + 32768) % 65536) - 32768 for s in self._body.steps
            )

    # -- physics -------------------------------------------------------------------

    def advance(self, now: float | None = None) -> None:
        """Integrate the wheels up to ``now`` (exact arcs for constant wheel speeds)."""
        with self._lock:
            now = self.clock() if now is None else now
            dt = now - self._t
            if dt <= 0:
                return
            self._t = now
            b = self._body
            left, right = (self.motor_rate(v) for v in b.speed_steps)
            ground_left, ground_right = self.wheels.ground(left, right)  # less the slip
            vl = ground_left * METRES_PER_STEP
            vr = ground_right * METRES_PER_STEP
            v = (vl + vr) / 2
            w = (vr - vl) / AXLE_M
            b.steps[0] += self.wheels.counted(left * dt, self.noise)
            b.steps[1] += self.wheels.counted(right * dt, self.noise)
            if abs(w) < 1e-9:
                nx = b.x_m + v * dt * math.cos(b.theta_rad)
                ny = b.y_m + v * dt * math.sin(b.theta_rad)
            else:
                r = v / w
                nx = b.x_m + r * (math.sin(b.theta_rad + w * dt) - math.sin(b.theta_rad))
                ny = b.y_m - r * (math.cos(b.theta_rad + w * dt) - math.cos(b.theta_rad))
            b.theta_rad = (b.theta_rad + w * dt + math.pi) % (2 * math.pi) - math.pi
            nx, ny = self._resolve_collisions(nx, ny)
            self.distance_travelled_m += math.hypot(nx - b.x_m, ny - b.y_m)
            b.x_m, b.y_m = nx, ny
            # Smoothed accelerations over ~50 ms, as the accelerometer's filter would.
            alpha = min(1.0, dt / 0.05)
            b.forward_acc += alpha * ((v - b.forward_mps) / dt - b.forward_acc)
            b.forward_mps = v
            b.lateral_acc += alpha * (v * w - b.lateral_acc)
            self.closest_approach_m = min(self.closest_approach_m, self._clearance())

    def _resolve_collisions(self, x: float, y: float) -> tuple[float, float]:
        """Keep the body inside the walls and outside the blocks (the wheels slip)."""
        hx, hy = self.arena.half_extents
        x = min(max(x, -(hx - ROBOT_RADIUS_M)), hx - ROBOT_RADIUS_M)
        y = min(max(y, -(hy - ROBOT_RADIUS_M)), hy - ROBOT_RADIUS_M)
        for blk in self.blocks:
            lx, ly = blk.to_local(x, y)
            bx, by = blk.half_extents
            cx, cy = min(max(lx, -bx), bx), min(max(ly, -by), by)
            d = math.hypot(lx - cx, ly - cy)
            if d >= ROBOT_RADIUS_M:
                continue
            if d < 1e-9:  # the centre got inside the box: out through its x face
                lx = math.copysign(bx + ROBOT_RADIUS_M, lx if lx else 1.0)
            else:  # touch the nearest point of the box from outside
                lx = cx + (lx - cx) / d * ROBOT_RADIUS_M
                ly = cy + (ly - cy) / d * ROBOT_RADIUS_M
            x, y = blk.to_world(lx, ly)
        for ox, oy in self._others():  # another e-puck: two discs that may not overlap
            d = math.hypot(x - ox, y - oy)
            if d < 2 * ROBOT_RADIUS_M:
                away = (x - ox, y - oy) if d > 1e-9 else (1.0, 0.0)
                scale = 2 * ROBOT_RADIUS_M / (d if d > 1e-9 else 1.0)
                x, y = ox + away[0] * scale, oy + away[1] * scale
        return x, y

    def _others(self) -> list[tuple[float, float]]:
        """Where the other robots of this world's crowd are (none outside a swarm)."""
        return self.crowd.others(self) if self.crowd is not None else []

    def body_position(self) -> tuple[float, float]:
        """Where this robot's body is, without advancing it (for the crowd's others)."""
        return self._body.x_m, self._body.y_m

    # -- ground-truth devices (a world file may declare them; a real e-puck has none) --

    def declared_devices(self) -> frozenset[str]:
        """Which of "gps", "compass", "touch sensor" this world gives the robot."""
        return self.devices

    def gps_position(self) -> tuple[float, float, float]:
        """The robot's centre in metres, Webots' ENU frame (x east, y north, z up)."""
        with self._lock:
            self.advance()
            return (self._body.x_m, self._body.y_m, 0.0)

    def compass_vector(self) -> tuple[float, float, float]:
        """North (+y) in the robot's frame (x forward, y left, z up), as Webots' Compass."""
        with self._lock:
            self.advance()
            theta = self._body.theta_rad
            return (math.sin(theta), math.cos(theta), 0.0)

    def touching(self) -> bool:
        """Whether the body touches a wall or a box (a bumper's TouchSensor)."""
        with self._lock:
            self.advance()
            return self._clearance() <= 0.0005

    def _clearance(self) -> float:
        b = self._body
        hx, hy = self.arena.half_extents
        gaps = [hx - abs(b.x_m), hy - abs(b.y_m)]
        for blk in self.blocks:
            lx, ly = blk.to_local(b.x_m, b.y_m)
            bx, by = blk.half_extents
            gaps.append(math.hypot(max(abs(lx) - bx, 0.0), max(abs(ly) - by, 0.0)))
        for ox, oy in self._others():
            gaps.append(math.hypot(b.x_m - ox, b.y_m - oy) - ROBOT_RADIUS_M)
        return max(0.0, min(gaps) - ROBOT_RADIUS_M)

    def ray_distance(self, ox: float, oy: float, angle: float) -> float:
        """Distance from (ox, oy) along ``angle`` to the first wall or block face."""
        c, s = math.cos(angle), math.sin(angle)
        best = math.inf
        for pos, d, h in zip((ox, oy), (c, s), self.arena.half_extents, strict=True):
            if abs(d) > 1e-12:
                best = min(best, ((h if d > 0 else -h) - pos) / d)
        for blk in self.blocks:
            t = ray_box(ox, oy, c, s, blk)
            if t is not None:
                best = min(best, t)
        for px, py in self._others():
            t = ray_disc(ox, oy, c, s, px, py, ROBOT_RADIUS_M)
            if t is not None:
                best = min(best, t)
        return max(best, 0.0)

    # -- sensors -------------------------------------------------------------------

    def _noise(self, sigma: float) -> float:
        return float(self._rng.normal(0.0, sigma)) if self.noise and sigma > 0 else 0.0

    def _sensor_origin(self, bearing: float) -> tuple[float, float, float]:
        b = self._body
        a = b.theta_rad + bearing
        return (b.x_m + ROBOT_RADIUS_M * math.cos(a), b.y_m + ROBOT_RADIUS_M * math.sin(a), a)

    def _ir_value(self, bearing: float, scale: float = 1.0) -> int:
        ox, oy, a = self._sensor_origin(bearing)
        # A beam about 17 degrees wide: the nearest of three rays.
        d = min(self.ray_distance(ox, oy, a + da) for da in (-0.15, 0.0, 0.15)) / scale
        value = float(np.interp(d, [p[0] for p in IR_RESPONSE], [p[1] for p in IR_RESPONSE]))
        value += self._noise(0.02 * value + 3.0)
        return int(round(min(4095.0, max(-20.0, value))))

    def proximity(self, long_range: bool = False) -> list[int]:
        """ps0..ps7 (and IR8, IR9 of the Overo board, which reach four times as far)."""
        with self._lock:
            self.advance()
            values = [self._ir_value(a) for a in SENSOR_BEARINGS_RAD]
            if long_range:
                values += [self._ir_value(a, scale=4.0) for a in LONG_RANGE_BEARINGS_RAD]
            return values

    def true_proximity(self) -> list[float]:
        """Noise-free proximity, for tests that check the world's response."""
        with self._lock:
            noise, self.noise = self.noise, False
            try:
                return [float(v) for v in self.proximity()]
            finally:
                self.noise = noise

    def light(self, long_range: bool = False) -> list[int]:
        """ls0..ls7, 0..4095, lower is brighter: the lamp's light on each sensor's face."""
        with self._lock:
            self.advance()
            values = []
            bearings = SENSOR_BEARINGS_RAD + (LONG_RANGE_BEARINGS_RAD if long_range else ())
            for bearing in bearings:
                ox, oy, a = self._sensor_origin(bearing)
                dx, dy = self.lamp.x_m - ox, self.lamp.y_m - oy
                d2 = dx * dx + dy * dy + self.lamp.height_m**2
                facing = 0.5 + 0.5 * math.cos(math.atan2(dy, dx) - a)
                illum = facing * 0.25**2 / (d2 + 0.25**2 - self.lamp.height_m**2)
                value = 4000.0 - 3600.0 * min(1.0, illum) + self._noise(4.0)
                values.append(int(round(min(4095.0, max(0.0, value)))))
            return values

    def floor_reflectance(self, x_m: np.ndarray, y_m: np.ndarray) -> np.ndarray:
        """1.0 on the white floor, 0.15 on black (the floor's marks or line track)."""
        x = np.asarray(x_m, dtype=float)
        y = np.asarray(y_m, dtype=float)
        return self.floor_pattern.reflectance(x, y)

    def floor_rgb_at(self, x_m: np.ndarray, y_m: np.ndarray) -> np.ndarray:
        """The floor's colour where the camera looks, (..., 3) uint8."""
        if isinstance(self.floor_pattern, ImageFloor):
            x, y = np.asarray(x_m, dtype=float), np.asarray(y_m, dtype=float)
            return self.floor_pattern.rgb(x, y)
        r = self.floor_reflectance(x_m, y_m)
        grey = (40 + 200 * r).astype(np.uint8)
        return np.stack([grey, grey, grey], axis=-1)

    def floor(self) -> list[int]:
        """gs0..gs2: about 1000 on white, 300 on black."""
        with self._lock:
            self.advance()
            b = self._body
            c, s = math.cos(b.theta_rad), math.sin(b.theta_rad)
            xs = np.array([b.x_m + f * c - left * s for f, left in FLOOR_SENSOR_OFFSETS_M])
            ys = np.array([b.y_m + f * s + left * c for f, left in FLOOR_SENSOR_OFFSETS_M])
            refl = self.floor_reflectance(xs, ys)
            return [int(round(200 + 800 * r + self._noise(5.0))) for r in refl]

    def accelerometer_raw(
        self, zero: int = ACC_ZERO, per_g: int = ACC_PER_G
    ) -> tuple[int, int, int]:
        """ADC counts: 0 g at ``zero``, ``per_g`` counts a g; z sees gravity, x/y see motion.

        Webots' conversion (docs/protocol.md) is x = -(g/800)(raw-2000), y and z =
        +(g/800)(raw-2000), so x carries the lateral (centripetal) and y the forward
        acceleration. An e-puck rev 1.3 read over Bluetooth gives 0 g at 2048 and about
        750 counts a g (e_acc.c, e_get_acc_filtered).
        """
        with self._lock:
            self.advance()
            k = per_g / GRAVITY
            x = zero - k * self._body.lateral_acc + self._noise(2.0)
            y = zero + k * self._body.forward_acc + self._noise(2.0)
            z = zero + per_g + self._noise(2.0)
            return (int(round(x)), int(round(y)), int(round(z)))

    def accelerometer_spherical(
        self, zero: int = ACC_ZERO, per_g: int = ACC_PER_G
    ) -> tuple[float, float, float]:
        """(magnitude, orientation, inclination) as e_acc.c computes them, in float32.

        The counts less the offsets measured at start-up (z's less one g of GRAVITY), the
        magnitude in counts, and the angles with CST_RADIAN = 180/3.1415, so that they may
        overshoot 0..360 and 0..180 a little; the orientation is 0 when the inclination
        is under 5 or over 160 degrees.
        """
        return spherical_from_raw(self.accelerometer_raw(zero, per_g), zero, per_g)

    def microphone_buffer(self) -> tuple[list[list[int]], int]:
        """The circular buffers of the three microphones and the slot the ADC writes next
        (firmware_sim.epuck_model.microphone_buffers)."""
        with self._lock:
            self.advance()
            b = self._body
            rng = self._rng if self.noise else None
            return microphone_buffers(self._t, (b.x_m, b.y_m, b.theta_rad), self.sound, rng)

    def microphone_amplitudes(self) -> list[int]:
        """Max - min over the last 100 samples of each microphone."""
        buffers, _ = self.microphone_buffer()
        return [max(b) - min(b) for b in buffers]
