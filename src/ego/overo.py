"""The user-facing E-GO functions of the thesis' appendix C, same names and meanings.

They act on one default robot, opened by ``overo_serial_init(baudrate, dev_name)``.
Device tags (``dt``) are Webots device names or the integer tags that
``wb_robot_get_device`` returns. Units are E-GO's own: raw counts, steps, steps/s,
RGB888 images. Each function is a thin delegation to the core devices. As in the Webots
faces, a sensor read before it is enabled and sampled gives NaN.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from ego.controller.camera import Camera
from ego.controller.distance_sensor import DistanceSensor
from ego.controller.light_sensor import LightSensor
from ego.controller.position_sensor import encoder_steps, whole_steps
from ego.devices.accelerometer import AccelerometerMode
from ego.devices.table import DEVICES, names_of, spec
from ego.errors import UnknownDeviceError
from ego.faces import default_robot
from ego.faces.tags import name_of
from ego.webots import (
    wb_camera_image_get_blue,
    wb_camera_image_get_green,
    wb_camera_image_get_grey,
    wb_camera_image_get_red,
)

__all__ = [
    "overo_accelerometer_disable",
    "overo_accelerometer_enable_raw",
    "overo_accelerometer_enable_spherical",
    "overo_accelerometer_get_value",
    "overo_camera_brightness_control",
    "overo_camera_brigthness_control",
    "overo_camera_contrast_control",
    "overo_camera_enable",
    "overo_camera_get_blue",
    "overo_camera_get_fov",
    "overo_camera_get_green",
    "overo_camera_get_grey",
    "overo_camera_get_height",
    "overo_camera_get_image",
    "overo_camera_get_red",
    "overo_camera_get_width",
    "overo_camera_init",
    "overo_camera_saturation_control",
    "overo_camera_save_image",
    "overo_camera_set_fov",
    "overo_camera_set_height",
    "overo_camera_set_width",
    "overo_distance_sensors_disable",
    "overo_distance_sensors_enable",
    "overo_distance_sensors_get_value",
    "overo_encoders_disable",
    "overo_encoders_enable",
    "overo_encoders_get_left",
    "overo_encoders_get_right",
    "overo_encoders_set",
    "overo_led_set",
    "overo_light_sensors_disable",
    "overo_light_sensors_enable",
    "overo_light_sensors_get_value",
    "overo_microphone_disable",
    "overo_microphone_enable",
    "overo_microphone_enable_buffer",
    "overo_microphone_get_buffer",
    "overo_microphone_get_volume",
    "overo_motors_set_speed",
    "overo_scheduler_local_get_time",
    "overo_scheduler_robot_step",
    "overo_serial_close",
    "overo_serial_init",
]

Tag = int | str

_NAN = float("nan")


def _expect(dt: Tag, family: str) -> str:
    """The name of ``dt``, a device of ``family`` (a Robot attribute) in the device table."""
    name = name_of(dt)
    names = names_of(family)
    if name not in names:
        raise UnknownDeviceError(f"device {name!r} is not one of {', '.join(names)}")
    return name


def _expect_kind(dt: Tag, kind: str, what: str) -> str:
    """The name of ``dt``, a device of Webots kind ``kind`` in the device table."""
    name = name_of(dt)
    if spec(name).kind != kind:
        families = dict.fromkeys(s.family for s in DEVICES if s.kind == kind)
        spans = ", ".join(
            n[0] if len(n) == 1 else f"{n[0]}..{n[-1]}" for n in map(names_of, families)
        )
        raise UnknownDeviceError(f"device {name!r} is not {what} ({spans})")
    return name


# -- serial and scheduler (C.9, C.10) -------------------------------------------------------


def overo_serial_init(baudrate: int = 230400, dev_name: str | None = None) -> None:
    """Open the robot on ``dev_name`` (default: EGO_PORT, else /dev/ttyS0) at ``baudrate``."""
    default_robot.open_robot(dev_name, baudrate)


def overo_serial_close(port_fd: object = None) -> None:
    """Stop the robot and close its port (the argument is accepted for E-GO's signature)."""
    default_robot.close()


def overo_scheduler_robot_step(ms: int) -> int:
    """One time step of ``ms``; -1 once the link is lost or ``ego run --duration`` is used up."""
    return default_robot.step(ms)


def overo_scheduler_local_get_time() -> float:
    """Seconds of controller time since the start."""
    return default_robot.get().time_s


# -- accelerometer (C.1) ------------------------------------------------------------------


def overo_accelerometer_enable_raw(dt: Tag, ms: int) -> None:
    _expect(dt, "accelerometer")
    default_robot.get().accelerometer.enable(ms, mode=AccelerometerMode.RAW)


def overo_accelerometer_enable_spherical(dt: Tag, ms: int) -> None:
    _expect(dt, "accelerometer")
    default_robot.get().accelerometer.enable(ms, mode=AccelerometerMode.SPHERICAL)


def overo_accelerometer_get_value() -> list[float]:
    """Raw x, y, z counts, or magnitude, orientation, inclination: as enabled (NaN before)."""
    acc = default_robot.get().accelerometer
    if not (acc.enabled and acc.has_values):
        return [_NAN, _NAN, _NAN]
    if acc.mode is AccelerometerMode.SPHERICAL:
        return list(acc.spherical)
    return [float(v) for v in acc.values]


def overo_accelerometer_disable(dt: Tag) -> None:
    _expect(dt, "accelerometer")
    default_robot.get().accelerometer.disable()


# -- camera (C.2) -------------------------------------------------------------------------


def _cam(dt: Tag) -> Camera:
    return Camera(default_robot.get(), _expect(dt, "camera"))


def overo_camera_init() -> None:
    """Open the camera device (done at first use anyway)."""
    default_robot.get().camera  # noqa: B018  (the property opens it)


def overo_camera_enable(dt: Tag, ms: int) -> None:
    _cam(dt).enable(ms)


def overo_camera_get_image(dt: Tag) -> npt.NDArray[np.uint8]:
    """The last image, RGB888, shape (height, width, 3)."""
    _cam(dt)
    return default_robot.get().camera.image


def overo_camera_get_width(dt: Tag) -> int:
    return _cam(dt).getWidth()


def overo_camera_get_height(dt: Tag) -> int:
    return _cam(dt).getHeight()


def overo_camera_set_width(dt: Tag, width: int) -> None:
    _cam(dt)
    camera = default_robot.get().camera
    camera.set_size(width, camera.height)


def overo_camera_set_height(dt: Tag, height: int) -> None:
    _cam(dt)
    camera = default_robot.get().camera
    camera.set_size(camera.width, height)


def overo_camera_get_fov(dt: Tag) -> float:
    return _cam(dt).getFov()


def overo_camera_set_fov(dt: Tag, fov: float) -> None:
    _cam(dt)
    default_robot.get().camera.fov_rad = fov


def overo_camera_brightness_control(brightness_value: int) -> None:
    default_robot.get().camera.brightness = brightness_value


#: The thesis' own spelling.
overo_camera_brigthness_control = overo_camera_brightness_control


def overo_camera_contrast_control(contrast_value: int) -> None:
    default_robot.get().camera.contrast = contrast_value


def overo_camera_saturation_control(saturation_value: int) -> None:
    default_robot.get().camera.saturation = saturation_value


def overo_camera_save_image(dt: Tag, filename: str, quality: int) -> int:
    """PNG or JPEG by extension, JPEG quality 1-100; 0 on success, -1 on failure."""
    return _cam(dt).saveImage(filename, quality)


def _image_bytes(image: bytes | npt.NDArray[np.uint8]) -> bytes:
    return image.tobytes() if isinstance(image, np.ndarray) else bytes(image)


def overo_camera_get_red(
    dt: Tag, image: bytes | npt.NDArray[np.uint8], width: int, x: int, y: int
) -> int:
    _cam(dt)
    return wb_camera_image_get_red(_image_bytes(image), width, x, y)


def overo_camera_get_green(
    dt: Tag, image: bytes | npt.NDArray[np.uint8], width: int, x: int, y: int
) -> int:
    _cam(dt)
    return wb_camera_image_get_green(_image_bytes(image), width, x, y)


def overo_camera_get_blue(
    dt: Tag, image: bytes | npt.NDArray[np.uint8], width: int, x: int, y: int
) -> int:
    _cam(dt)
    return wb_camera_image_get_blue(_image_bytes(image), width, x, y)


def overo_camera_get_grey(
    dt: Tag, image: bytes | npt.NDArray[np.uint8], width: int, x: int, y: int
) -> int:
    _cam(dt)
    return wb_camera_image_get_grey(_image_bytes(image), width, x, y)


# -- distance sensors: proximity and floor (C.3) ------------------------------------------


def overo_distance_sensors_enable(dt: Tag, ms: int) -> None:
    DistanceSensor(default_robot.get(), _distance_name(dt)).enable(ms)


def overo_distance_sensors_get_value(dt: Tag) -> float:
    return DistanceSensor(default_robot.get(), _distance_name(dt)).getValue()


def overo_distance_sensors_disable(dt: Tag) -> None:
    DistanceSensor(default_robot.get(), _distance_name(dt)).disable()


def _distance_name(dt: Tag) -> str:
    return _expect_kind(dt, "DistanceSensor", "a distance sensor")


# -- encoders (C.4) -----------------------------------------------------------------------


def overo_encoders_enable(dt: Tag, ms: int) -> None:
    _expect(dt, "encoders")
    default_robot.get().encoders.enable(ms)


def overo_encoders_get_left() -> float:
    """Steps (NaN until the encoders are enabled and sampled)."""
    return encoder_steps(default_robot.get(), 0)


def overo_encoders_get_right() -> float:
    return encoder_steps(default_robot.get(), 1)


def overo_encoders_set(left: float, right: float) -> None:
    default_robot.get().encoders.set(whole_steps(left), whole_steps(right))


def overo_encoders_disable(dt: Tag) -> None:
    _expect(dt, "encoders")
    default_robot.get().encoders.disable()


# -- LEDs, light sensors, microphones, motors (C.5-C.8) -----------------------------------


def overo_led_set(dt: Tag, value: int) -> None:
    """0 off, 1 on, 2 toggle; an RGB LED (an e-puck2's led1, 3, 5, 7): its colour 0xRRGGBB."""
    default_robot.get().leds.set(name_of(dt), value)


def overo_light_sensors_enable(dt: Tag, ms: int) -> None:
    LightSensor(default_robot.get(), _light_name(dt)).enable(ms)


def overo_light_sensors_get_value(dt: Tag) -> float:
    return LightSensor(default_robot.get(), _light_name(dt)).getValue()


def overo_light_sensors_disable(dt: Tag) -> None:
    LightSensor(default_robot.get(), _light_name(dt)).disable()


def _light_name(dt: Tag) -> str:
    return _expect_kind(dt, "LightSensor", "a light sensor")


def overo_microphone_enable(dt: Tag, ms: int) -> None:
    default_robot.get().microphones.enable(ms, [_expect(dt, "microphones")])


def overo_microphone_get_volume(dt: Tag) -> float:
    """Amplitude 0..4095 (NaN until the microphone is enabled and sampled)."""
    name = _expect(dt, "microphones")
    mics = default_robot.get().microphones
    if mics.sampling_period(name) is None or not mics.has_values:
        return _NAN
    return float(mics.value(name))


def overo_microphone_disable(dt: Tag) -> None:
    default_robot.get().microphones.disable([_expect(dt, "microphones")])


def overo_microphone_enable_buffer(dt: Tag, ms: int) -> None:
    """Fetch the raw samples (all three microphones travel together) every ``ms``."""
    _expect(dt, "microphones")
    default_robot.get().microphones.enable_buffer(ms)


def overo_microphone_get_buffer(dt: Tag) -> npt.NDArray[np.uint16]:
    """The last 100 samples of one microphone at 16384 Hz, oldest first."""
    index = spec(_expect(dt, "microphones")).index
    samples: npt.NDArray[np.uint16] = default_robot.get().microphones.buffer[index]
    return samples


def overo_motors_set_speed(dt: Tag, left: float, right: float) -> None:
    """Both wheel speeds in steps/s, +-1000 (the tag names either wheel motor)."""
    _expect(dt, "motors")
    default_robot.get().motors.set_speed(left, right)
