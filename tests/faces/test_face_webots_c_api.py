"""The Webots C API names (appendix B) and wbr_* (C.12.2) behave on the emulator (item 5).

Every function is called with the integer tag that ``wb_robot_get_device`` returns and,
as the face allows, with the device's name: both must work alike.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator

import pytest

from ego import webots as wb
from ego.errors import EgoError
from ego.faces import default_robot, runtime
from ego.webots import Tag
from firmware_sim import Emulator, World
from firmware_sim.world import Pose

TIME_STEP = 32
Addressing = Callable[[str], Tag]


@pytest.fixture(params=["tag", "name"])
def device(
    request: pytest.FixtureRequest, face_options: runtime.RunOptions
) -> Iterator[Addressing]:
    """The robot opened with wb_robot_init(); devices addressed by integer tag or by name."""
    assert wb.wb_robot_init() == 1
    if request.param == "tag":
        yield wb.wb_robot_get_device
    else:
        yield lambda name: name
    wb.wb_robot_cleanup()


def step(times: int = 1) -> None:
    for _ in range(times):
        assert wb.wb_robot_step(TIME_STEP) == 0


def test_wb_robot_init_step_and_cleanup(face_options: runtime.RunOptions) -> None:
    assert wb.wb_robot_init() == 1
    assert wb.wb_robot_step(TIME_STEP) == 0
    assert wb.wb_robot_step(16) == 0
    assert default_robot.get().time_s == pytest.approx(0.048)
    wb.wb_robot_cleanup()
    assert not default_robot.is_open()
    with pytest.raises(EgoError, match="wb_robot_init"):
        wb.wb_robot_step(TIME_STEP)


def test_wb_robot_get_device_gives_each_name_its_own_fixed_tag(
    face_options: runtime.RunOptions,
) -> None:
    wb.wb_robot_init()
    names = [
        *(f"ps{i}" for i in range(8)),
        *(f"gs{i}" for i in range(3)),
        *(f"ls{i}" for i in range(8)),
        *(f"led{i}" for i in range(10)),
        "accelerometer",
        "left wheel motor",
        "right wheel motor",
        "left wheel sensor",
        "right wheel sensor",
        "camera",
    ]
    tags = [wb.wb_robot_get_device(name) for name in names]
    assert all(isinstance(t, int) and t > 0 for t in tags)
    assert len(set(tags)) == len(names)
    assert [wb.wb_robot_get_device(name) for name in names] == tags


def test_wb_robot_step_ends_the_run_when_its_duration_is_up(
    face_options: runtime.RunOptions,
) -> None:
    face_options.duration_s = 0.064
    wb.wb_robot_init()
    assert [wb.wb_robot_step(TIME_STEP) for _ in range(3)] == [0, 0, -1]
    assert not default_robot.is_open()


def test_wb_distance_sensor_reads_proximity_and_floor(device: Addressing, world: World) -> None:
    ps0, gs1 = device("ps0"), device("gs1")
    assert math.isnan(wb.wb_distance_sensor_get_value(ps0))  # not enabled: NaN, as Webots
    wb.wb_distance_sensor_enable(ps0, TIME_STEP)
    wb.wb_distance_sensor_enable(gs1, TIME_STEP)
    assert math.isnan(wb.wb_distance_sensor_get_value(ps0))  # enabled, not yet sampled
    world.place(Pose(0.0, 0.0, 0.0))
    step()
    far = wb.wb_distance_sensor_get_value(ps0)
    world.place(Pose(0.46, 0.0, 0.0))  # nose against the x = 0.5 wall
    step()
    near = wb.wb_distance_sensor_get_value(ps0)
    assert far < 200 < 800 < near
    assert wb.wb_distance_sensor_get_value(gs1) > 800  # white floor

    wb.wb_distance_sensor_disable(ps0)
    step()
    assert math.isnan(wb.wb_distance_sensor_get_value(ps0))
    assert not math.isnan(wb.wb_distance_sensor_get_value(gs1))


def test_wb_light_sensor_is_lower_facing_the_lamp(device: Addressing, world: World) -> None:
    ls0 = device("ls0")
    wb.wb_light_sensor_enable(ls0, TIME_STEP)
    heading = math.atan2(world.lamp.y_m, world.lamp.x_m)
    world.place(Pose(0.0, 0.0, heading))
    step()
    towards = wb.wb_light_sensor_get_value(ls0)
    world.place(Pose(0.0, 0.0, heading + math.pi))
    step()
    away = wb.wb_light_sensor_get_value(ls0)
    assert towards < away - 400
    wb.wb_light_sensor_disable(ls0)
    assert math.isnan(wb.wb_light_sensor_get_value(ls0))


def test_wb_accelerometer_gives_gravity_in_metres_per_second_squared(device: Addressing) -> None:
    acc = device("accelerometer")
    assert all(math.isnan(v) for v in wb.wb_accelerometer_get_values(acc))
    wb.wb_accelerometer_enable(acc, TIME_STEP)
    step(2)
    x, y, z = wb.wb_accelerometer_get_values(acc)
    assert z == pytest.approx(9.81, abs=0.2)
    assert abs(x) < 0.3 and abs(y) < 0.3
    wb.wb_accelerometer_disable(acc)
    assert all(math.isnan(v) for v in wb.wb_accelerometer_get_values(acc))


def test_wb_differential_wheels_drive_and_count(
    device: Addressing, world: World, wait_until: Callable[..., bool]
) -> None:
    assert math.isnan(wb.wb_differential_wheels_get_left_encoder())
    wb.wb_differential_wheel_enable_encoders(TIME_STEP)  # the thesis' spelling
    wb.wb_differential_wheels_set_encoders(500, -500)
    wb.wb_differential_wheels_set_speed(400, -400)
    step()
    assert world.speeds == (400, -400)
    first = (
        wb.wb_differential_wheels_get_left_encoder(),
        wb.wb_differential_wheels_get_right_encoder(),
    )
    assert first == pytest.approx((500, -500), abs=5)
    step(10)
    assert wb.wb_differential_wheels_get_left_encoder() > first[0] + 50
    assert wb.wb_differential_wheels_get_right_encoder() < first[1] - 50

    wb.wb_differential_wheels_disable_encoders()
    wb.wb_differential_wheels_set_speed(0, 0)
    step()
    assert wait_until(lambda: world.speeds == (0, 0))
    assert math.isnan(wb.wb_differential_wheels_get_left_encoder())
    wb.wb_differential_wheels_enable_encoders(TIME_STEP)
    step()
    assert wb.wb_differential_wheels_get_right_encoder() < first[1] - 50


def test_wb_led_set_switches_off_on_zero_and_on_otherwise(
    device: Addressing, world: World, wait_until: Callable[..., bool]
) -> None:
    wb.wb_led_set(device("led4"), 1)
    wb.wb_led_set(device("led8"), 7)  # Webots: any non-zero value is on
    step()
    assert wait_until(lambda: world.leds[4] == 1 and world.leds[8] == 1), world.leds
    wb.wb_led_set(device("led4"), 0)
    step()
    assert wait_until(lambda: world.leds[4] == 0), world.leds
    assert world.leds[8] == 1
    wb.wb_led_set(device("led8"), 0)


def test_wbr_init_step_stop_and_cleanup(
    emulator: Emulator, world: World, wait_until: Callable[..., bool]
) -> None:
    assert wb.wbr_init(emulator.path) == 1
    try:
        assert not wb.wbr_has_failed()
        wb.wb_differential_wheels_set_speed(250, 250)
        wb.wb_led_set(wb.wb_robot_get_device("led0"), 1)
        assert wb.wbr_robot_step(TIME_STEP) == 0
        assert wait_until(lambda: world.speeds == (250, 250) and world.leds[0] == 1)

        wb.wbr_stop_actuators()
        assert wait_until(lambda: world.speeds == (0, 0) and not any(world.leds))
        assert wb.wbr_robot_step(TIME_STEP) == 0  # nothing left to re-send
        assert world.speeds == (0, 0)
        assert not wb.wbr_has_failed()
    finally:
        wb.wbr_robot_cleanup()
    assert not default_robot.is_open()


def test_wbr_init_on_a_missing_port_fails_softly(tmp_path: object) -> None:
    assert wb.wbr_init("/dev/ttyEGO-not-there") == 0
    assert wb.wbr_has_failed()
    assert not default_robot.is_open()
