"""The Webots Python controller API for the e-puck, over ego: ``from controller import Robot``.

``ego run my_controller.py`` makes the module name ``controller`` resolve here, so a
controller written for Webots runs unchanged on the real robot (or the emulator, or a
robot across the network). Units are Webots': rad/s, rad, m/s^2, BGRA camera bytes.
Reading a sensor that is not enabled gives NaN, as in Webots.

Each class lives in the module Webots names for it (``controller.distance_sensor``
holds ``DistanceSensor``), as Webots' own ``controller`` package lays them out.
"""

from ego.controller.accelerometer import Accelerometer
from ego.controller.altimeter import Altimeter
from ego.controller.ansi_codes import AnsiCodes
from ego.controller.brake import Brake
from ego.controller.camera import Camera, CameraRecognitionObject
from ego.controller.compass import Compass
from ego.controller.connector import Connector
from ego.controller.device import Device
from ego.controller.display import Display
from ego.controller.distance_sensor import DistanceSensor
from ego.controller.emitter import Emitter
from ego.controller.field import Field
from ego.controller.gps import GPS
from ego.controller.gyro import Gyro
from ego.controller.inertial_unit import InertialUnit
from ego.controller.joystick import Joystick
from ego.controller.keyboard import Keyboard
from ego.controller.led import LED
from ego.controller.lidar import Lidar
from ego.controller.lidar_point import LidarPoint
from ego.controller.light_sensor import LightSensor
from ego.controller.motion import Motion
from ego.controller.motor import Motor
from ego.controller.mouse import Mouse
from ego.controller.node import Node
from ego.controller.pen import Pen
from ego.controller.position_sensor import PositionSensor
from ego.controller.radar import Radar
from ego.controller.radar_target import RadarTarget
from ego.controller.range_finder import RangeFinder
from ego.controller.receiver import Receiver
from ego.controller.robot import DifferentialWheels, Robot
from ego.controller.sensor import Sensor
from ego.controller.skin import Skin
from ego.controller.speaker import Speaker
from ego.controller.supervisor import Supervisor
from ego.controller.touch_sensor import TouchSensor
from ego.controller.vacuum_gripper import VacuumGripper

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
