"""Each device's values move as the emulator's world says they should (issue 3, item 1)."""

from __future__ import annotations

import math
import time
from collections.abc import Callable

import numpy as np
import pytest

import ego
from ego.errors import UnsupportedDeviceError
from firmware_sim import World
from firmware_sim.world import Pose

STEP_MS = 32


def run(robot: ego.Robot, steps: int, ms: int = STEP_MS) -> None:
    for _ in range(steps):
        assert robot.step(ms) == 0


def facing(world: World, x: float, y: float, away: bool = False) -> Pose:
    """A pose at (x, y) facing the lamp (or facing away from it)."""
    heading = math.atan2(world.lamp.y_m - y, world.lamp.x_m - x)
    return Pose(x, y, heading + (math.pi if away else 0.0))


# -- proximity -------------------------------------------------------------------------


def test_front_proximity_rises_when_driving_at_a_wall(sim_robot: ego.Robot, world: World) -> None:
    world.place(Pose(0.40, 0.0, 0.0))  # facing +x, 6 cm from the x = 0.5 wall
    sim_robot.proximity.enable(STEP_MS)
    run(sim_robot, 1)
    far = sim_robot.proximity.values
    sim_robot.motors.set_speed(500, 500)
    front: list[int] = []
    for _ in range(40):  # 1.3 s at 6.4 cm/s: the body reaches the wall
        run(sim_robot, 1)
        front.append(max(sim_robot.proximity.value("ps0"), sim_robot.proximity.value("ps7")))
    sim_robot.motors.set_speed(0, 0)
    run(sim_robot, 1)
    near = sim_robot.proximity.values

    assert max(far[0], far[7]) < 200, far
    assert front[-1] > 1000, front
    assert front[-1] > 5 * max(far[0], far[7])
    # The rear sensors (ps3, ps4) face open space all along.
    assert max(near[3], near[4]) < 200, near


def test_proximity_is_noisy_but_close_to_the_noise_free_truth(
    sim_robot: ego.Robot, world: World
) -> None:
    world.place(Pose(0.42, 0.0, 0.0))
    sim_robot.proximity.enable(STEP_MS)
    run(sim_robot, 1)
    truth = world.true_proximity()
    for measured, expected in zip(sim_robot.proximity.values, truth, strict=True):
        assert measured == pytest.approx(expected, rel=0.15, abs=15)


# -- encoders --------------------------------------------------------------------------


def test_encoders_count_speed_times_time(sim_robot: ego.Robot, world: World) -> None:
    sim_robot.encoders.enable(STEP_MS)
    run(sim_robot, 1)
    left0, right0 = sim_robot.encoders.values
    sim_robot.motors.set_speed(500, -300)
    # The step's batch goes out as step() starts (D before Q): bracket the drive with the
    # host clock the world also runs on, so a late step cannot skew the expectation.
    started = time.monotonic()
    run(sim_robot, 30)
    elapsed_s = time.monotonic() - started
    sim_robot.motors.set_speed(0, 0)
    run(sim_robot, 1)
    left, right = sim_robot.encoders.values

    assert left - left0 == pytest.approx(500 * elapsed_s, rel=0.03, abs=3)
    assert right - right0 == pytest.approx(-300 * elapsed_s, rel=0.03, abs=3)


def test_encoders_unwrap_past_the_int16_counters(sim_robot: ego.Robot, world: World) -> None:
    sim_robot.encoders.enable(STEP_MS)
    sim_robot.encoders.set(32000, -32000)
    sim_robot.motors.set_speed(1000, -1000)  # spin in place: left up, right down
    totals: list[tuple[int, int]] = []
    for _ in range(35):  # 1.1 s at 1000 steps/s: both counters cross +-32768
        run(sim_robot, 1)
        totals.append(sim_robot.encoders.values)
    raw_left, raw_right = world.steps_int16()
    sim_robot.motors.set_speed(0, 0)
    run(sim_robot, 1)

    lefts = [t[0] for t in totals]
    rights = [t[1] for t in totals]
    assert lefts[0] == pytest.approx(32000, abs=5)  # P went before Q in the same batch
    assert lefts == sorted(lefts), lefts  # monotonic: no jump back at the wrap
    assert rights == sorted(rights, reverse=True), rights
    assert lefts[-1] > 32767 + 200
    assert rights[-1] < -32768 - 200
    # The firmware's own counters did wrap: ego's totals are not what the wire said.
    assert raw_left < 0 < raw_right


def test_encoder_set_is_read_back_in_the_same_step(sim_robot: ego.Robot) -> None:
    sim_robot.encoders.enable(STEP_MS)
    run(sim_robot, 1)
    sim_robot.encoders.set(1234, -4321)
    run(sim_robot, 1)
    assert sim_robot.encoders.values == (1234, -4321)


# -- light, floor, accelerometer ---------------------------------------------------------


def test_light_is_lower_facing_the_lamp_than_facing_away(
    sim_robot: ego.Robot, world: World
) -> None:
    sim_robot.light.enable(STEP_MS)
    world.place(facing(world, 0.0, 0.0))
    run(sim_robot, 1)
    towards = sim_robot.light.values
    world.place(facing(world, 0.0, 0.0, away=True))
    run(sim_robot, 1)
    away = sim_robot.light.values

    # ls0 and ls7 look ahead; brighter is lower (protocol.md).
    assert towards[0] + towards[7] < away[0] + away[7] - 800, (towards, away)
    assert towards[3] + towards[4] > away[3] + away[4] + 800, (towards, away)


def test_floor_values_drop_over_the_black_stripe(sim_robot: ego.Robot, world: World) -> None:
    sim_robot.floor.enable(STEP_MS)
    world.place(Pose(0.0, 0.0, 0.0))
    run(sim_robot, 1)
    white = sim_robot.floor.values
    world.place(Pose(-0.03, 0.2, 0.0))  # the sensors, 3 cm ahead, sit on the y = 0.2 stripe
    run(sim_robot, 1)
    black = sim_robot.floor.values

    assert min(white) > 800, white
    assert max(black) < 500, black
    assert sim_robot.floor.value("gs1") == black[1]


def test_accelerometer_reads_gravity_on_z_at_rest(sim_robot: ego.Robot) -> None:
    sim_robot.accelerometer.enable(STEP_MS)
    run(sim_robot, 2)
    x, y, z = sim_robot.accelerometer.acceleration_mps2
    assert z == pytest.approx(9.81, abs=0.2)
    assert abs(x) < 0.2 and abs(y) < 0.2
    raw_z = sim_robot.accelerometer.values[2]
    assert raw_z == pytest.approx(2000 + 800, abs=20)  # 0 g near 2000, 800 counts a g


def test_accelerometer_spherical_sees_one_g_straight_down(sim_robot: ego.Robot) -> None:
    """e_acc.c: the magnitude is in counts less the offsets e_acc_calibr took at rest, z's
    less GRAVITY (e_acc.h: 768): a robot at rest reads 768."""
    sim_robot.accelerometer.enable(STEP_MS, mode="spherical")
    run(sim_robot, 2)
    magnitude, _orientation, inclination = sim_robot.accelerometer.spherical
    assert magnitude == pytest.approx(768, abs=25)
    assert inclination == pytest.approx(0.0, abs=3.0)


# -- microphones -----------------------------------------------------------------------


def test_microphone_amplitude_grows_nearer_the_source(sim_robot: ego.Robot, world: World) -> None:
    sim_robot.microphones.enable(STEP_MS)
    world.place(Pose(world.sound.x_m + 0.1, world.sound.y_m, 0.0))
    run(sim_robot, 1)
    near = sim_robot.microphones.values
    world.place(Pose(0.4, -0.4, 0.0))
    run(sim_robot, 1)
    far = sim_robot.microphones.values

    assert len(near) == len(far) == 3
    assert all(n > 2 * f for n, f in zip(near, far, strict=True)), (near, far)


def test_microphone_buffer_is_three_by_one_hundred_adc_counts(sim_robot: ego.Robot) -> None:
    """e_micro.c: unsigned 12-bit ADC samples around mid-scale, not zero-mean."""
    sim_robot.microphones.enable_buffer(64)
    run(sim_robot, 1)
    buffer = sim_robot.microphones.buffer
    assert buffer.shape == (3, 100)
    assert buffer.dtype == np.uint16
    assert (buffer <= 4095).all()
    # A 1 kHz tone sampled at 16384 Hz swings both ways around mid-scale.
    middle = np.median(buffer, axis=1, keepdims=True).astype(int)
    assert (buffer.max(axis=1) > middle[:, 0] + 50).all()
    assert (buffer.min(axis=1) < middle[:, 0] - 50).all()
    assert (abs(middle - 2048) < 600).all()


# -- actuators -------------------------------------------------------------------------


def test_led_set_and_toggle_reach_the_world(
    sim_robot: ego.Robot, world: World, wait_until: Callable[..., bool]
) -> None:
    sim_robot.leds.set("led0", 1)
    sim_robot.leds.set(8, ego.LedValue.ON)
    sim_robot.leds.set("led9", 1)
    run(sim_robot, 1)
    assert wait_until(lambda: world.leds == (1, 0, 0, 0, 0, 0, 0, 0, 1, 1)), world.leds

    sim_robot.leds.set("led0", 2)  # toggle: off
    sim_robot.leds.set(3, 2)  # toggle: on
    run(sim_robot, 1)
    assert wait_until(lambda: world.leds == (0, 0, 0, 1, 0, 0, 0, 0, 1, 1)), world.leds
    assert sim_robot.leds.get("led0") == 0
    assert sim_robot.leds.get(3) == 1


def test_motor_readback_equals_commanded_speeds(sim_robot: ego.Robot, world: World) -> None:
    sim_robot.motors.enable(STEP_MS)
    sim_robot.motors.set_speed(123, -456)
    run(sim_robot, 1)
    assert sim_robot.motors.values == (123, -456)
    assert world.speeds == (123, -456)
    sim_robot.motors.set_speed(-1000, 1000)
    run(sim_robot, 1)
    assert sim_robot.motors.values == (-1000, 1000)
    sim_robot.motors.set_speed(0, 0)
    run(sim_robot, 1)
    assert sim_robot.motors.values == (0, 0)


def test_fractional_speeds_are_rounded_to_whole_steps(sim_robot: ego.Robot) -> None:
    sim_robot.motors.enable(STEP_MS)
    sim_robot.motors.set_speed(100.4, -99.6)
    run(sim_robot, 1)
    assert sim_robot.motors.values == (100, -100)
    sim_robot.motors.set_speed(np.int64(250), np.float32(-250.0))  # numpy numbers are numbers
    run(sim_robot, 1)
    assert sim_robot.motors.values == (250, -250)
    sim_robot.motors.set_speed(0, 0)


# -- the stock GCtronic firmware in Overo mode -------------------------------------------


def test_overo_firmware_serves_long_range_ps8_and_ps9(overo_robot: ego.Robot) -> None:
    assert overo_robot.channel.info.firmware is ego.Firmware.GCTRONIC
    assert overo_robot.proximity.member_names[-2:] == ("ps8", "ps9")
    assert "ps9" in overo_robot.device_names
    overo_robot.proximity.enable(STEP_MS)
    overo_robot.light.enable(STEP_MS)
    run(overo_robot, 1)
    assert len(overo_robot.proximity.values) == 10
    assert overo_robot.proximity.value("ps8") > 0
    assert len(overo_robot.light.values) == 8  # the two extra O values are not light sensors


def test_overo_firmware_refuses_the_floor_sensors(overo_robot: ego.Robot) -> None:
    with pytest.raises(UnsupportedDeviceError, match="floor"):
        overo_robot.floor.enable(STEP_MS)
    assert not overo_robot.floor.enabled


@pytest.mark.parametrize("led", ["led8", "led9", 8, 9])
def test_overo_firmware_refuses_the_body_and_front_leds(
    overo_robot: ego.Robot, led: str | int
) -> None:
    with pytest.raises(UnsupportedDeviceError, match="led0, led1"):
        overo_robot.leds.set(led, 1)


def test_thesis_firmware_has_no_ps8(sim_robot: ego.Robot) -> None:
    assert sim_robot.proximity.member_names == tuple(f"ps{i}" for i in range(8))
    with pytest.raises(ego.errors.UnknownDeviceError, match="ps7"):
        sim_robot.device("ps8")
