"""The Webots Python controller API for the e-puck, over ego: ``from controller import Robot``.

``ego run my_controller.py`` makes the module name ``controller`` resolve here, so a
controller written for Webots runs unchanged on the real robot (or the emulator, or a
robot across the network). Units are Webots': rad/s, rad, m/s^2, BGRA camera bytes.
Reading a sensor that is not enabled gives NaN, as in Webots.
"""

from ego.controller.devices import (
    LED,
    Accelerometer,
    Camera,
    Device,
    DistanceSensor,
    LightSensor,
    Motor,
    PositionSensor,
)
from ego.controller.robot import DifferentialWheels, Robot

__all__ = [
    "LED",
    "Accelerometer",
    "Camera",
    "Device",
    "DifferentialWheels",
    "DistanceSensor",
    "LightSensor",
    "Motor",
    "PositionSensor",
    "Robot",
]
