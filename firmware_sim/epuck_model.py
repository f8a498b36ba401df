"""The e-puck as the emulator models it: its geometry, its sensors' placement and
response, the firmware's stepping and scales, and what its microphones hear of a source
(firmware_sim.world moves the robot and reads these).

Geometry (e-puck): body 75 mm across, wheel radius 20.5 mm, axle 52 mm, 1000 steps a
wheel turn, speeds clamped to +-1000 steps/s.
"""

from __future__ import annotations

import math

import numpy as np

from firmware_sim.layout import SoundSource

__all__ = [
    "IR_RESPONSE",
    "ROBOT_RADIUS_M",
    "microphone_buffers",
    "spherical_from_raw",
    "stepping_rate",
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


def microphone_buffers(
    now: float, pose: tuple[float, float, float], sound: SoundSource,
    rng: np.random.Generator | None,
) -> tuple[list[list[int]], int]:
    """The circular buffers of the three microphones at ``now`` and the slot the ADC
    writes next, for a robot at ``pose`` (x, y, heading) hearing ``sound``; ``rng``
    adds the ADC's noise.

    e_ad_conv.c / e_micro.c: unsigned 12-bit samples around mid-scale (2048 is
    silence) at 16384 Hz; the index (e_last_mic_scan_id) is the next slot to write,
    which holds the oldest sample.
    """
    x_m, y_m, theta = pose
    c, s = math.cos(theta), math.sin(theta)
    k = np.arange(MIC_SAMPLES)
    written = int(now * MIC_RATE_HZ)
    next_slot = written % MIC_SAMPLES
    # Slot i was last written (next_slot - 1 - i) mod 100 samples ago.
    age = (next_slot - 1 - k) % MIC_SAMPLES
    t = now - age / MIC_RATE_HZ
    buffers = []
    for f, left in MIC_OFFSETS_M:
        mx, my = x_m + f * c - left * s, y_m + f * s + left * c
        d = math.hypot(sound.x_m - mx, sound.y_m - my)
        amp = sound.amplitude / (1.0 + d / 0.1)
        wave = amp * np.sin(2 * np.pi * sound.frequency_hz * (t - d / 343.0))
        if rng is not None:
            wave = wave + rng.normal(0.0, 3.0, MIC_SAMPLES)
        counts = np.clip(np.round(MIC_MIDSCALE + wave), 0, 4095)
        buffers.append([int(v) for v in counts])
    return buffers, next_slot


def spherical_from_raw(
    raw: tuple[int, int, int], zero: int, per_g: int
) -> tuple[float, float, float]:
    """(magnitude, orientation, inclination) of raw counts ``raw`` as e_acc.c computes
    them, in float32 (0 g at ``zero``, ``per_g`` counts a g)."""
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
