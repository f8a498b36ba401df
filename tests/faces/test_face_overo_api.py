"""The E-GO functions of appendix C (``ego.overo``) behave on the emulator (item 5).

Device tags are Webots names or the integer tags of ``wb_robot_get_device``: both work.
Units are E-GO's own: raw counts, steps, steps/s. Camera functions are tested with the
camera.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator

import numpy as np
import pytest

from ego import overo as ov
from ego.faces import default_robot, runtime
from ego.webots import Tag, wb_robot_get_device
from firmware_sim import Emulator, World
from firmware_sim.world import Pose

TIME_STEP = 32
Addressing = Callable[[str], Tag]


@pytest.fixture(params=["tag", "name"])
def device(
    request: pytest.FixtureRequest, emulator: Emulator, face_options: runtime.RunOptions
) -> Iterator[Addressing]:
    """The robot opened with overo_serial_init(); devices addressed by tag or by name."""
    ov.overo_serial_init(230400, emulator.path)
    yield wb_robot_get_device if request.param == "tag" else (lambda name: name)
    ov.overo_serial_close()


def step(times: int = 1) -> None:
    for _ in range(times):
        assert ov.overo_scheduler_robot_step(TIME_STEP) == 0


def test_serial_init_scheduler_and_close(emulator: Emulator, face_options: object) -> None:
    ov.overo_serial_init(230400, emulator.path)
    assert default_robot.get().port == emulator.path
    assert ov.overo_scheduler_local_get_time() == 0.0
    step(3)
    assert ov.overo_scheduler_robot_step(10) == 0
    assert ov.overo_scheduler_local_get_time() == pytest.approx(0.106)
    ov.overo_serial_close()
    assert not default_robot.is_open()


def test_serial_init_without_a_port_uses_the_run_options(
    face_options: runtime.RunOptions, world: World
) -> None:
    ov.overo_serial_init()  # E-GO's defaults: 230400 baud, the configured port
    robot = default_robot.get()
    assert robot.port == face_options.port
    ov.overo_motors_set_speed("left wheel motor", 300, 300)
    step()
    assert ov.overo_scheduler_local_get_time() == pytest.approx(TIME_STEP / 1000)
    assert world.speeds == (300, 300)  # the batch went down the options' port
    ov.overo_serial_close(3)  # E-GO passes the port's file descriptor: accepted, unused
    assert not default_robot.is_open() and robot.closed


def test_accelerometer_raw_then_spherical(device: Addressing) -> None:
    acc = device("accelerometer")
    assert all(math.isnan(v) for v in ov.overo_accelerometer_get_value())
    ov.overo_accelerometer_enable_raw(acc, TIME_STEP)
    step()
    x, y, z = ov.overo_accelerometer_get_value()
    assert z == pytest.approx(2800, abs=25)  # raw counts: 0 g near 2000, 800 a g
    assert x == pytest.approx(2000, abs=25) and y == pytest.approx(2000, abs=25)

    ov.overo_accelerometer_enable_spherical(acc, TIME_STEP)
    step()
    magnitude, _orientation, inclination = ov.overo_accelerometer_get_value()
    assert magnitude == pytest.approx(768, abs=25)  # counts: e_acc.h GRAVITY at rest
    assert inclination == pytest.approx(0.0, abs=3.0)

    ov.overo_accelerometer_disable(acc)
    assert all(math.isnan(v) for v in ov.overo_accelerometer_get_value())


def test_distance_sensors_read_proximity_and_floor(device: Addressing, world: World) -> None:
    ps7, gs0 = device("ps7"), device("gs0")
    assert math.isnan(ov.overo_distance_sensors_get_value(ps7))
    ov.overo_distance_sensors_enable(ps7, TIME_STEP)
    ov.overo_distance_sensors_enable(gs0, TIME_STEP)
    world.place(Pose(0.0, 0.0, 0.0))
    step()
    far = ov.overo_distance_sensors_get_value(ps7)
    white = ov.overo_distance_sensors_get_value(gs0)
    world.place(Pose(0.46, -0.03, 0.0))  # the nose at the wall and ...
    step()
    near = ov.overo_distance_sensors_get_value(ps7)
    world.place(Pose(-0.03, 0.2, 0.0))  # ... the floor sensors over the black stripe
    step()
    black = ov.overo_distance_sensors_get_value(gs0)
    assert far < 200 < 800 < near
    assert black < 500 < 800 < white

    ov.overo_distance_sensors_disable(ps7)
    assert math.isnan(ov.overo_distance_sensors_get_value(ps7))


def test_encoders_count_set_and_disable(device: Addressing) -> None:
    left_sensor = device("left wheel sensor")
    assert math.isnan(ov.overo_encoders_get_left())
    ov.overo_encoders_enable(left_sensor, TIME_STEP)
    ov.overo_encoders_set(-200, 300)
    ov.overo_motors_set_speed(device("left wheel motor"), 500, 500)
    step()
    assert ov.overo_encoders_get_left() == pytest.approx(-200, abs=5)
    assert ov.overo_encoders_get_right() == pytest.approx(300, abs=5)
    step(8)
    assert ov.overo_encoders_get_left() > -200 + 60
    assert ov.overo_encoders_get_right() > 300 + 60
    ov.overo_motors_set_speed(device("right wheel motor"), 0, 0)
    ov.overo_encoders_disable(left_sensor)
    assert math.isnan(ov.overo_encoders_get_right())


def test_led_set_switches_and_toggles(
    device: Addressing, world: World, wait_until: Callable[..., bool]
) -> None:
    ov.overo_led_set(device("led6"), 1)
    ov.overo_led_set(device("led9"), 1)
    step()
    assert wait_until(lambda: world.leds[6] == 1 and world.leds[9] == 1), world.leds
    ov.overo_led_set(device("led6"), 2)  # toggle
    step()
    assert wait_until(lambda: world.leds[6] == 0), world.leds
    ov.overo_led_set(device("led9"), 0)
    step()
    assert wait_until(lambda: not any(world.leds)), world.leds


def test_light_sensors_are_lower_facing_the_lamp(device: Addressing, world: World) -> None:
    ls7 = device("ls7")
    assert math.isnan(ov.overo_light_sensors_get_value(ls7))
    ov.overo_light_sensors_enable(ls7, TIME_STEP)
    heading = math.atan2(world.lamp.y_m, world.lamp.x_m)
    world.place(Pose(0.0, 0.0, heading))
    step()
    towards = ov.overo_light_sensors_get_value(ls7)
    world.place(Pose(0.0, 0.0, heading + math.pi))
    step()
    away = ov.overo_light_sensors_get_value(ls7)
    assert towards < away - 400
    ov.overo_light_sensors_disable(ls7)
    assert math.isnan(ov.overo_light_sensors_get_value(ls7))


def test_microphone_volume_and_buffer(device: Addressing, world: World) -> None:
    mic1 = device("mic1")
    assert math.isnan(ov.overo_microphone_get_volume(mic1))
    ov.overo_microphone_enable(mic1, TIME_STEP)
    ov.overo_microphone_enable_buffer(mic1, 64)
    world.place(Pose(world.sound.x_m + 0.1, world.sound.y_m, 0.0))
    step()
    near = ov.overo_microphone_get_volume(mic1)
    samples = ov.overo_microphone_get_buffer(mic1)
    world.place(Pose(0.4, -0.4, 0.0))
    step()
    far = ov.overo_microphone_get_volume(mic1)
    assert near > 2 * far > 0
    assert samples.shape == (100,) and samples.dtype == np.uint16
    # ADC counts around mid-scale (e_micro.c): a tone swings both ways around 2048.
    assert samples.max() > 2048 + 50 and samples.min() < 2048 - 50

    ov.overo_microphone_disable(mic1)
    assert math.isnan(ov.overo_microphone_get_volume(mic1))


def test_motors_set_speed_in_steps_per_second(
    device: Addressing, world: World, wait_until: Callable[..., bool]
) -> None:
    ov.overo_motors_set_speed(device("left wheel motor"), 321, -123)
    step()
    assert wait_until(lambda: world.speeds == (321, -123)), world.speeds
    ov.overo_motors_set_speed(device("left wheel motor"), 0, 0)
    step()
    assert wait_until(lambda: world.speeds == (0, 0)), world.speeds
