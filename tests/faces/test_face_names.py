"""Every name of the thesis' appendices B and C that the faces promise exists (issue 3, item 5).

The lists below are the appendices', spelled out one name per entry (the appendices
abbreviate them as ``overo_accelerometer_enable_raw/_spherical, _get_value, _disable``...).
"""

from __future__ import annotations

import pytest

import ego.controller
from ego import overo, webots

OVERO_NAMES = [
    # C.1 accelerometer
    "overo_accelerometer_enable_raw",
    "overo_accelerometer_enable_spherical",
    "overo_accelerometer_get_value",
    "overo_accelerometer_disable",
    # C.2 camera (its behaviour is tested with the camera)
    "overo_camera_init",
    "overo_camera_enable",
    "overo_camera_get_image",
    "overo_camera_get_width",
    "overo_camera_get_height",
    "overo_camera_set_width",
    "overo_camera_set_height",
    "overo_camera_get_fov",
    "overo_camera_set_fov",
    "overo_camera_brigthness_control",  # sic, the thesis' spelling
    "overo_camera_brightness_control",
    "overo_camera_contrast_control",
    "overo_camera_saturation_control",
    "overo_camera_save_image",
    "overo_camera_get_red",
    "overo_camera_get_green",
    "overo_camera_get_blue",
    "overo_camera_get_grey",
    # C.3 distance sensors
    "overo_distance_sensors_enable",
    "overo_distance_sensors_get_value",
    "overo_distance_sensors_disable",
    # C.4 encoders
    "overo_encoders_enable",
    "overo_encoders_get_left",
    "overo_encoders_get_right",
    "overo_encoders_set",
    "overo_encoders_disable",
    # C.5 LEDs, C.6 light sensors
    "overo_led_set",
    "overo_light_sensors_enable",
    "overo_light_sensors_get_value",
    "overo_light_sensors_disable",
    # C.7 microphone (and the raw buffer)
    "overo_microphone_enable",
    "overo_microphone_get_volume",
    "overo_microphone_disable",
    "overo_microphone_enable_buffer",
    "overo_microphone_get_buffer",
    # C.8 motors, C.9 scheduler, C.10 serial
    "overo_motors_set_speed",
    "overo_scheduler_robot_step",
    "overo_scheduler_local_get_time",
    "overo_serial_init",
    "overo_serial_close",
]

WEBOTS_NAMES = [
    "wb_robot_init",
    "wb_robot_step",
    "wb_robot_get_device",
    "wb_robot_cleanup",
    # B.1 accelerometer
    "wb_accelerometer_enable",
    "wb_accelerometer_disable",
    "wb_accelerometer_get_values",
    # B.2 camera (its behaviour is tested with the camera)
    "wb_camera_enable",
    "wb_camera_disable",
    "wb_camera_get_fov",
    "wb_camera_set_fov",
    "wb_camera_get_width",
    "wb_camera_get_height",
    "wb_camera_get_image",
    "wb_camera_save_image",
    "wb_camera_image_get_red",
    "wb_camera_image_get_green",
    "wb_camera_image_get_blue",
    "wb_camera_image_get_grey",
    # B.3 differential wheels
    "wb_differential_wheels_set_speed",
    "wb_differential_wheel_enable_encoders",  # sic, the thesis' spelling
    "wb_differential_wheels_enable_encoders",
    "wb_differential_wheels_disable_encoders",
    "wb_differential_wheels_get_left_encoder",
    "wb_differential_wheels_get_right_encoder",
    "wb_differential_wheels_set_encoders",
    # B.4 distance sensors, B.5 LEDs, B.6 light sensors
    "wb_distance_sensor_enable",
    "wb_distance_sensor_disable",
    "wb_distance_sensor_get_value",
    "wb_led_set",
    "wb_light_sensor_enable",
    "wb_light_sensor_disable",
    "wb_light_sensor_get_value",
    # C.12.2 remote control
    "wbr_init",
    "wbr_robot_step",
    "wbr_robot_cleanup",
    "wbr_stop_actuators",
    "wbr_has_failed",
]

CONTROLLER_NAMES = {
    "Robot": [
        "step",
        "getDevice",
        "getBasicTimeStep",
        "getTime",
        "getName",
        "getMode",
        "getDistanceSensor",
        "getMotor",
        "getLED",
        "getLightSensor",
        "getCamera",
        "getAccelerometer",
        "getPositionSensor",
    ],
    "DistanceSensor": ["enable", "disable", "getSamplingPeriod", "getValue"],
    "LightSensor": ["enable", "disable", "getSamplingPeriod", "getValue"],
    "Accelerometer": ["enable", "disable", "getSamplingPeriod", "getValues"],
    "PositionSensor": ["enable", "disable", "getSamplingPeriod", "getValue"],
    "Motor": ["setPosition", "setVelocity", "getVelocity", "getMaxVelocity"],
    "LED": ["set", "get"],
    "Camera": [
        "enable",
        "disable",
        "getSamplingPeriod",
        "getImage",
        "getImageArray",
        "imageGetRed",
        "imageGetGreen",
        "imageGetBlue",
        "imageGetGray",
        "getWidth",
        "getHeight",
        "saveImage",
    ],
    "DifferentialWheels": [
        "setSpeed",
        "enableEncoders",
        "disableEncoders",
        "getLeftEncoder",
        "getRightEncoder",
        "setEncoders",
        "step",
        "getDevice",
    ],
}


@pytest.mark.parametrize("name", OVERO_NAMES)
def test_every_e_go_name_of_appendix_c_exists(name: str) -> None:
    assert callable(getattr(overo, name, None)), f"ego.overo has no {name}"
    assert name in overo.__all__


@pytest.mark.parametrize("name", WEBOTS_NAMES)
def test_every_webots_c_name_of_appendix_b_exists(name: str) -> None:
    assert callable(getattr(webots, name, None)), f"ego.webots has no {name}"
    assert name in webots.__all__


@pytest.mark.parametrize("cls", sorted(CONTROLLER_NAMES))
def test_every_webots_python_class_has_its_methods(cls: str) -> None:
    assert cls in ego.controller.__all__
    klass = getattr(ego.controller, cls)
    missing = [m for m in CONTROLLER_NAMES[cls] if not callable(getattr(klass, m, None))]
    assert not missing, f"{cls} lacks {missing}"


def test_the_misspelt_thesis_names_are_aliases_of_the_right_ones() -> None:
    assert overo.overo_camera_brigthness_control is overo.overo_camera_brightness_control
    assert (
        webots.wb_differential_wheel_enable_encoders
        is webots.wb_differential_wheels_enable_encoders
    )
