"""The e-puck's device families, one module each, all sans-I/O.

Each family turns its state into requests for the step's batch and takes the values of
the replies back; ``ego.Robot`` owns one of each and sends what they ask, one batch a step.
"""

from ego.devices.accelerometer import Accelerometer
from ego.devices.base import Actuator, ArraySensor, Device, Sensor
from ego.devices.battery import Battery
from ego.devices.encoders import Encoders
from ego.devices.floor import FloorSensors
from ego.devices.leds import Leds
from ego.devices.light import LightSensors
from ego.devices.microphones import Microphones
from ego.devices.motors import Motors
from ego.devices.proximity import ProximitySensors

__all__ = [
    "Accelerometer",
    "Actuator",
    "ArraySensor",
    "Battery",
    "Device",
    "Encoders",
    "FloorSensors",
    "Leds",
    "LightSensors",
    "Microphones",
    "Motors",
    "ProximitySensors",
    "Sensor",
]
