"""A small world for the emulated e-puck: a walled arena, a lamp, a sound source, a floor pattern.

Values move the way a real robot's do: the step counters integrate the wheel speeds (the
wheels slip a little, and the counters are a little noisy: firmware_sim.wheels),
proximity follows the e-puck IR response to the nearest surface, light falls (lower is
brighter) as the lamp gets nearer, the accelerometer sees gravity and motion, and the
microphones hear the source. Time is the host's monotonic clock, so a controller that
drives for one second moves the robot one second's worth.

Geometry (e-puck): body 75 mm across, wheel radius 20.5 mm, axle 52 mm, 1000 steps a
wheel turn, speeds clamped to +-1000 steps/s. Frame: x east, y north, theta = 0 faces
+x, counter-clockwise positive.
"""

from __future__ import annotations

import math
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from firmware_sim.floor import ImageFloor, LineTrack, Marks, Plain
from firmware_sim.markers import Marker
from firmware_sim.wheels import WheelModel, Wheels

Floor = Marks | LineTrack | Plain | ImageFloor

__all__ = [
    "IR_RESPONSE",
    "Arena",
    "Block",
    "Lamp",
    "Pose",
    "SoundSource",
    "World",
]

ROBOT_RADIUS_M = 0.0375
WHEEL_RADIUS_M = 0.0205
AXLE_M = 0.052
STEPS_PER_TURN = 1000
MAX_SPEED_STEPS = 1000
METRES_PER_STEP = 2 * math.pi * WHEEL_RADIUS_M / STEPS_PER_TURN
GRAVITY = 9.81
ACC_ZERO = 2000  # raw accelerometer counts at 0 g (docs/protocol.md)
ACC_PER_G = 800

#: Webots' e-puck IR table: distance from the body (m) -> raw value.
IR_RESPONSE = (
    (0.0, 4095.0),
    (0.005, 2133.0),
    (0.01, 1466.0),
    (0.02, 384.0),
    (0.05, 120.0),
    (0.07, 67.0),
)
#: Sensor bearings from the heading, CCW positive (ps0 front-right ... ps7 front-left).
SENSOR_BEARINGS_RAD = (-0.30, -0.80, -1.57, -2.64, 2.64, 1.57, 0.80, 0.30)
#: The Overo board's long-range IR8 (left) and IR9 (right), facing ahead-left/right.
LONG_RANGE_BEARINGS_RAD = (0.5, -0.5)
#: Floor sensors: (forward, left) offsets from the centre, left / centre / right.
FLOOR_SENSOR_OFFSETS_M = ((0.03, 0.012), (0.032, 0.0), (0.03, -0.012))
#: Microphones: mic0 right, mic1 left, mic2 back (forward, left offsets).
MIC_OFFSETS_M = ((0.0, -0.03), (0.0, 0.03), (-0.03, 0.0))
MIC_RATE_HZ = 16384
MIC_SAMPLES = 100
#: The ADC count of silence: the microphones' signal sits at mid-scale.
MIC_MIDSCALE = 2048


@dataclass(frozen=True, slots=True)
class Pose:
    x_m: float
    y_m: float
    theta_rad: float


@dataclass(frozen=True, slots=True)
class Arena:
    """A walled arena: walls at x = +-half_size_m and y = +-half_y_m (square unless a
    world file gives it two sides, as Webots' RectangleArena's floorSize does)."""

    half_size_m: float = 0.5
    wall_rgb: tuple[int, int, int] = (200, 190, 170)
    half_y_m: float | None = None
    wall_height_m: float = 0.10

    @property
    def half_extents(self) -> tuple[float, float]:
        return self.half_size_m, self.half_size_m if self.half_y_m is None else self.half_y_m


@dataclass(frozen=True, slots=True)
class Block:
    """A box standing on the floor: an obstacle with a colour to follow. Square, 5 cm high
    and axis-aligned unless a world file gives it two sides, a height and a yaw (the
    boxes of a Webots world); ``half_size_m`` is its half extent along its own x."""

    x_m: float
    y_m: float
    half_size_m: float
    rgb: tuple[int, int, int]
    half_y_m: float | None = None
    yaw_rad: float = 0.0
    height_m: float = 0.05
    #: Its DEF name in a world file, if it has one (a Supervisor finds it by it).
    name: str | None = None

    @property
    def half_extents(self) -> tuple[float, float]:
        return self.half_size_m, self.half_size_m if self.half_y_m is None else self.half_y_m

    def to_local(self, x: float, y: float) -> tuple[float, float]:
        """A world point in the box's frame (centred, its sides along the axes)."""
        c, s = math.cos(self.yaw_rad), math.sin(self.yaw_rad)
        dx, dy = x - self.x_m, y - self.y_m
        return c * dx + s * dy, c * dy - s * dx

    def to_world(self, lx: float, ly: float) -> tuple[float, float]:
        c, s = math.cos(self.yaw_rad), math.sin(self.yaw_rad)
        return self.x_m + c * lx - s * ly, self.y_m + s * lx + c * ly


@dataclass(frozen=True, slots=True)
class Lamp:
    x_m: float = 0.3
    y_m: float = 0.3
    height_m: float = 0.15


@dataclass(frozen=True, slots=True)
class SoundSource:
    x_m: float = -0.3
    y_m: float = 0.3
    frequency_hz: float = 1000.0
    amplitude: float = 900.0  # ADC counts at 10 cm


def _default_blocks() -> list[Block]:
    return [
        Block(0.25, -0.25, 0.04, (200, 30, 30)),
        Block(-0.25, -0.22, 0.04, (30, 160, 40)),
        Block(-0.3, 0.05, 0.03, (30, 60, 200)),
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


#: e_acc.h GRAVITY: what one g reads as in A's magnitude, after e_acc_calibr.
SPHERICAL_ONE_G = 768
#: e_motors.c: a motor steps once every whole number of ticks of a 10 kHz timer.
STEP_TIMER_HZ = 10000
#: Asercom.c, 'b' on a rev 1.3: getBatteryValueRaw(), an ADC count. The source gives no
#: figure for a charged battery; this one is inferred (about 3.9 V through the divider).
BATTERY_RAW = 3012


def stepping_rate(speed_steps: int) -> float:
    """The rate a wheel really steps at for a commanded speed (e_motors.c).

    The firmware clamps to +-1000 and steps every ``10000 // |v|`` timer ticks, so 950
    runs at 1000 steps/s and 600 at 625.
    """
    v = max(-MAX_SPEED_STEPS, min(MAX_SPEED_STEPS, int(speed_steps)))
    return 0.0 if v == 0 else math.copysign(STEP_TIMER_HZ / (STEP_TIMER_HZ // abs(v)), v)


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
        self.blocks = _default_blocks() if blocks is None else list(blocks)
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
            t = _ray_box(ox, oy, c, s, blk)
            if t is not None:
                best = min(best, t)
        for px, py in self._others():
            t = _ray_disc(ox, oy, c, s, px, py, ROBOT_RADIUS_M)
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
        raw = self.accelerometer_raw(zero, per_g)
        f = np.float32
        x, y = f(raw[0] - zero), f(raw[1] - zero)
        # e_acc_calibr: centre_z = the reading at rest less GRAVITY (768, e_acc.h), so a
        # robot at rest reads 768 on z whatever its accelerometer's own scale.
        z = f(raw[2] - (zero + per_g - SPHERICAL_ONE_G))
        k = f(180.0) / f(3.1415)
        magnitude = np.sqrt(x * x + y * y + z * z, dtype=np.float32)
        horizontal = np.sqrt(x * x + y * y, dtype=np.float32)
        inclination = f(90.0) - f(np.arctan2(z, horizontal)) * k
        if inclination < 5 or inclination > 160:
            orientation = f(0.0)
        else:
            orientation = f(np.arctan2(x, y)) * k + f(180.0)
        return (float(magnitude), float(orientation), float(inclination))

    def microphone_buffer(self) -> tuple[list[list[int]], int]:
        """The circular buffers of the three microphones and the slot the ADC writes next.

        e_ad_conv.c / e_micro.c: unsigned 12-bit samples around mid-scale (2048 is
        silence) at 16384 Hz; the index (e_last_mic_scan_id) is the next slot to write,
        which holds the oldest sample.
        """
        with self._lock:
            self.advance()
            now = self._t
            b = self._body
            c, s = math.cos(b.theta_rad), math.sin(b.theta_rad)
            k = np.arange(MIC_SAMPLES)
            written = int(now * MIC_RATE_HZ)
            next_slot = written % MIC_SAMPLES
            # Slot i was last written (next_slot - 1 - i) mod 100 samples ago.
            age = (next_slot - 1 - k) % MIC_SAMPLES
            t = now - age / MIC_RATE_HZ
            buffers = []
            for f, left in MIC_OFFSETS_M:
                mx, my = b.x_m + f * c - left * s, b.y_m + f * s + left * c
                d = math.hypot(self.sound.x_m - mx, self.sound.y_m - my)
                amp = self.sound.amplitude / (1.0 + d / 0.1)
                wave = amp * np.sin(2 * np.pi * self.sound.frequency_hz * (t - d / 343.0))
                if self.noise:
                    wave = wave + self._rng.normal(0.0, 3.0, MIC_SAMPLES)
                counts = np.clip(np.round(MIC_MIDSCALE + wave), 0, 4095)
                buffers.append([int(v) for v in counts])
            return buffers, next_slot

    def microphone_amplitudes(self) -> list[int]:
        """Max - min over the last 100 samples of each microphone."""
        buffers, _ = self.microphone_buffer()
        return [max(b) - min(b) for b in buffers]


def _ray_box(ox: float, oy: float, c: float, s: float, blk: Block) -> float | None:
    """Slab test in the box's frame: distance along the ray to the box, or None."""
    lx, ly = blk.to_local(ox, oy)
    bc, bs = math.cos(blk.yaw_rad), math.sin(blk.yaw_rad)
    dx, dy = bc * c + bs * s, bc * s - bs * c
    bx, by = blk.half_extents
    t0, t1 = -math.inf, math.inf
    for o, d, h in ((lx, dx, bx), (ly, dy, by)):
        if abs(d) < 1e-12:
            if not -h <= o <= h:
                return None
            continue
        a, b = (-h - o) / d, (h - o) / d
        t0, t1 = max(t0, min(a, b)), min(t1, max(a, b))
    if t1 < max(t0, 0.0):
        return None
    return max(t0, 0.0)


def _ray_disc(
    ox: float, oy: float, c: float, s: float, px: float, py: float, radius: float
) -> float | None:
    """Distance along the ray to a disc (another e-puck's body), or None if it misses."""
    mx, my = ox - px, oy - py
    b = mx * c + my * s
    disc = b * b - (mx * mx + my * my - radius * radius)
    if disc < 0:
        return None
    t = -b - math.sqrt(disc)
    return t if t >= 0 else None
