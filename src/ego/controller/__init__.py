"""The Webots Python controller API for the e-puck, over ego: ``from controller import Robot``.

``ego run my_controller.py`` makes the module name ``controller`` resolve here, so a
controller written for Webots runs unchanged on the real robot (or the emulator, or a
robot across the network). Units are Webots': rad/s, rad, m/s^2, BGRA camera bytes.
Reading a sensor that is not enabled gives NaN, as in Webots.
"""

from ego.controller.absent import (
    GPS,
    Altimeter,
    Brake,
    CameraRecognitionObject,
    Compass,
    Connector,
    Display,
    Field,
    InertialUnit,
    Lidar,
    LidarPoint,
    Motion,
    Node,
    Pen,
    Radar,
    RadarTarget,
    RangeFinder,
    Skin,
    TouchSensor,
    VacuumGripper,
)
from ego.controller.devices import (
    LED,
    Accelerometer,
    Camera,
    Device,
    DistanceSensor,
    Gyro,
    LightSensor,
    Motor,
    PositionSensor,
    Sensor,
    Speaker,
)
from ego.controller.inputs import Joystick, Keyboard, Mouse
from ego.controller.radio import Emitter, Receiver
from ego.controller.robot import DifferentialWheels, Robot
from ego.controller.supervision import Supervisor
from ego.controller.terminal_colours import AnsiCodes

__all__ = [
    "GPS",
    "LED",
    "Accelerometer",
    "Altimeter",
    "AnsiCodes",
    "Brake",
    "Camera",
    "CameraRecognitionObject",
    "Compass",
    "Connector",
    "Device",
    "DifferentialWheels",
    "Display",
    "DistanceSensor",
    "Emitter",
    "Field",
    "Gyro",
    "InertialUnit",
    "Joystick",
    "Keyboard",
    "Lidar",
    "LidarPoint",
    "LightSensor",
    "Motion",
    "Motor",
    "Mouse",
    "Node",
    "Pen",
    "PositionSensor",
    "Radar",
    "RadarTarget",
    "RangeFinder",
    "Receiver",
    "Robot",
    "Sensor",
    "Skin",
    "Speaker",
    "Supervisor",
    "TouchSensor",
    "VacuumGripper",
]
