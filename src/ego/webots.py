"""The Webots C API names of the thesis' appendix B, and the remote-control entry points of C.12.2.

Each function is a one-line delegation to the device views of :mod:`ego.controller`
acting on one default robot; tags are the integers ``wb_robot_get_device`` returns (or
device names). As in the thesis' appendix B, ``wb_camera_get_image`` returns RGB888
bytes (3 a pixel) and the ``wb_camera_image_get_*`` helpers read that layout.
"""

from __future__ import annotations

import logging
from typing import TypeVar

from ego.controller.accelerometer import Accelerometer
from ego.controller.camera import Camera, webots_camera_size
from ego.controller.device import Device, view_class
from ego.controller.distance_sensor import DistanceSensor
from ego.controller.gyro import Gyro
from ego.controller.led import LED
from ego.controller.light_sensor import LightSensor
from ego.controller.position_sensor import encoder_steps, whole_steps
from ego.errors import EgoError, OutOfRangeError, UnknownDeviceError
from ego.faces import default_robot
from ego.faces.tags import name_of, tag_of

__all__ = [
    "wb_accelerometer_disable",
    "wb_accelerometer_enable",
    "wb_accelerometer_get_values",
    "wb_camera_disable",
    "wb_camera_enable",
    "wb_camera_get_fov",
    "wb_camera_get_height",
    "wb_camera_get_image",
    "wb_camera_get_width",
    "wb_camera_image_get_blue",
    "wb_camera_image_get_green",
    "wb_camera_image_get_grey",
    "wb_camera_image_get_red",
    "wb_camera_save_image",
    "wb_camera_set_fov",
    "wb_differential_wheel_enable_encoders",
    "wb_differential_wheels_disable_encoders",
    "wb_differential_wheels_enable_encoders",
    "wb_differential_wheels_get_left_encoder",
    "wb_differential_wheels_get_right_encoder",
    "wb_differential_wheels_set_encoders",
    "wb_differential_wheels_set_speed",
    "wb_distance_sensor_disable",
    "wb_distance_sensor_enable",
    "wb_distance_sensor_get_value",
    "wb_gyro_disable",
    "wb_gyro_enable",
    "wb_gyro_get_values",
    "wb_led_set",
    "wb_light_sensor_disable",
    "wb_light_sensor_enable",
    "wb_light_sensor_get_value",
    "wb_robot_cleanup",
    "wb_robot_get_device",
    "wb_robot_init",
    "wb_robot_step",
    "wbr_has_failed",
    "wbr_init",
    "wbr_robot_cleanup",
    "wbr_robot_step",
    "wbr_stop_actuators",
]

log = logging.getLogger(__name__)

Tag = int | str
_V = TypeVar("_V", bound=Device)


def _view(tag: Tag, cls: type[_V], strict: bool | None = None) -> _V:
    """The device ``tag`` names, as a ``cls``; a device of another kind is refused, as
    Webots refuses ``wb_distance_sensor_enable`` on a light sensor's tag."""
    robot = default_robot.get()
    name = name_of(tag)
    if view_class(name) is not cls:
        valid = [n for n in robot.device_names if view_class(n) is cls]
        kind = cls.__name__
        article = "an" if kind[0] in "AEIOU" else "a"
        raise UnknownDeviceError(
            f"device {name!r} is not {article} {kind}; valid names: {', '.join(valid)}"
        )
    return cls(robot, name, strict=strict)


def _distance(tag: Tag) -> DistanceSensor:
    return _view(tag, DistanceSensor)


def _light(tag: Tag) -> LightSensor:
    return _view(tag, LightSensor)


def _camera(tag: Tag) -> Camera:
    return _view(tag, Camera)


def _accelerometer(tag: Tag) -> Accelerometer:
    return _view(tag, Accelerometer)


# -- robot -------------------------------------------------------------------------------


def wb_robot_init() -> int:
    default_robot.open_robot()
    return 1


def wb_robot_step(ms: int) -> int:
    return default_robot.step(ms)


def wb_robot_get_device(name: str) -> int:
    robot = default_robot.get()
    if name not in robot.device_names:
        robot.device(name)  # raises UnknownDeviceError listing the valid names
    return tag_of(name)


def wb_robot_cleanup() -> None:
    default_robot.close()


# -- accelerometer -----------------------------------------------------------------------


def wb_accelerometer_enable(tag: Tag, ms: int) -> None:
    _accelerometer(tag).enable(ms)


def wb_accelerometer_disable(tag: Tag) -> None:
    _accelerometer(tag).disable()


def wb_accelerometer_get_values(tag: Tag) -> list[float]:
    return _accelerometer(tag).getValues()


# -- camera ------------------------------------------------------------------------------


def wb_camera_enable(tag: Tag, ms: int) -> None:
    camera = _camera(tag)
    webots_camera_size(default_robot.get())  # the size a Webots controller expects
    camera.enable(ms)


def wb_camera_disable(tag: Tag) -> None:
    _camera(tag).disable()


def wb_camera_get_fov(tag: Tag) -> float:
    return _camera(tag).getFov()


def wb_camera_set_fov(tag: Tag, fov: float) -> None:
    _camera(tag)  # checks the tag
    default_robot.get().camera.fov_rad = fov


def wb_camera_get_width(tag: Tag) -> int:
    return _camera(tag).getWidth()


def wb_camera_get_height(tag: Tag) -> int:
    return _camera(tag).getHeight()


def wb_camera_get_image(tag: Tag) -> bytes:
    """RGB888, 3 bytes a pixel, row by row (thesis appendix B)."""
    _camera(tag)
    return default_robot.get().camera.image.tobytes()


def wb_camera_save_image(tag: Tag, filename: str, quality: int) -> int:
    return _camera(tag).saveImage(filename, quality)


def _rgb(image: bytes, width: int, x: int, y: int, channel: int) -> int:
    height = len(image) // (3 * width) if width > 0 else 0
    if not (0 <= x < width and 0 <= y < height):
        raise OutOfRangeError(f"pixel ({x}, {y}) is outside the {width}x{height} image")
    return image[3 * (y * width + x) + channel]


def wb_camera_image_get_red(image: bytes, width: int, x: int, y: int) -> int:
    return _rgb(image, width, x, y, 0)


def wb_camera_image_get_green(image: bytes, width: int, x: int, y: int) -> int:
    return _rgb(image, width, x, y, 1)


def wb_camera_image_get_blue(image: bytes, width: int, x: int, y: int) -> int:
    return _rgb(image, width, x, y, 2)


def wb_camera_image_get_grey(image: bytes, width: int, x: int, y: int) -> int:
    return sum(_rgb(image, width, x, y, c) for c in range(3)) // 3


# -- differential wheels -----------------------------------------------------------------


def wb_differential_wheels_set_speed(left: float, right: float) -> None:
    """Wheel speeds in steps/s, +-1000."""
    default_robot.get().motors.set_speed(left, right)


def wb_differential_wheels_enable_encoders(ms: int) -> None:
    default_robot.get().encoders.enable(ms)


#: The thesis' appendix B spells it so.
wb_differential_wheel_enable_encoders = wb_differential_wheels_enable_encoders


def wb_differential_wheels_disable_encoders() -> None:
    default_robot.get().encoders.disable()


def wb_differential_wheels_get_left_encoder() -> float:
    """Steps (NaN until the encoders are enabled and sampled)."""
    return encoder_steps(default_robot.get(), 0)


def wb_differential_wheels_get_right_encoder() -> float:
    return encoder_steps(default_robot.get(), 1)


def wb_differential_wheels_set_encoders(left: float, right: float) -> None:
    default_robot.get().encoders.set(whole_steps(left), whole_steps(right))


# -- distance and light sensors, LEDs ------------------------------------------------------


def wb_distance_sensor_enable(tag: Tag, ms: int) -> None:
    _distance(tag).enable(ms)


def wb_distance_sensor_disable(tag: Tag) -> None:
    _distance(tag).disable()


def wb_distance_sensor_get_value(tag: Tag) -> float:
    return _distance(tag).getValue()


def wb_gyro_enable(tag: Tag, ms: int) -> None:
    _view(tag, Gyro).enable(ms)


def wb_gyro_disable(tag: Tag) -> None:
    _view(tag, Gyro).disable()


def wb_gyro_get_values(tag: Tag) -> list[float]:
    """x, y, z as Webots' gyro gives them (NaN while not enabled)."""
    return _view(tag, Gyro).getValues()


def wb_led_set(tag: Tag, value: int) -> None:
    """An int, as C's ``wb_led_set`` takes (a float or a bool is a TypeError here); an
    RGB LED's value is its colour ``0xRRGGBB``."""
    _view(tag, LED, strict=True).set(value)


def wb_light_sensor_enable(tag: Tag, ms: int) -> None:
    _light(tag).enable(ms)


def wb_light_sensor_disable(tag: Tag) -> None:
    _light(tag).disable()


def wb_light_sensor_get_value(tag: Tag) -> float:
    return _light(tag).getValue()


# -- remote control (appendix C.12.2) ------------------------------------------------------


def wbr_init(args: str | None = None) -> int:
    """Connect to the robot at ``args`` (a port or tcp://, udp:// URL); 1 on success, 0 not."""
    context = default_robot.current_context()
    try:
        context.open_robot(args)
    except EgoError as exc:
        log.warning("wbr_init(%r) failed: %s", args, exc)  # the caller only sees 0
        context.failed = True
        return 0
    context.failed = False
    return 1


def wbr_robot_step(ms: int) -> int:
    context = default_robot.current_context()
    result = context.step(ms)
    context.failed = context.failed or result == -1
    return result


def wbr_robot_cleanup() -> None:
    default_robot.close()


def wbr_stop_actuators() -> None:
    default_robot.get().stop_actuators()


def wbr_has_failed() -> bool:
    return default_robot.current_context().failed
