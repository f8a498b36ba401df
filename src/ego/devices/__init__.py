"""The e-puck's device families, one module each, all sans-I/O.

Each family turns its state into requests for the step's batch and takes the values of
the replies back; ``ego.Robot`` owns one of each and sends what they ask, one batch a step.

Each family's class declares it, once (``@TABLE.declare``, ego.devices.table). This
package imports every family module, so that importing any of ego's devices declares
them all: in this order, the order a telemetry sample and the dashboard list them.
"""

# The families, in the order a sample lists them (their declarations run here).
# isort: off
from ego.devices.proximity import ProximitySensors
from ego.devices.light import LightSensors
from ego.devices.floor import FloorSensors
from ego.devices.accelerometer import Accelerometer
from ego.devices.encoders import Encoders
from ego.devices.microphones import Microphones
from ego.devices.motors import Motors
from ego.devices.leds import Leds
from ego.devices.battery import Battery
from ego.devices.tof import TofSensor
from ego.devices.gyro import Gyro
from ego.devices.magnetometer import Magnetometer
from ego.devices.temperature import Temperature
from ego.devices.button import Button
from ego.devices.selector import Selector
from ego.devices.sound import Speaker

# isort: on
from ego.devices.base import Actuator, ArraySensor, Device, Sensor

__all__ = [
    "Accelerometer",
    "Actuator",
    "ArraySensor",
    "Battery",
    "Button",
    "Device",
    "Encoders",
    "FloorSensors",
    "Gyro",
    "Leds",
    "LightSensors",
    "Magnetometer",
    "Microphones",
    "Motors",
    "ProximitySensors",
    "Selector",
    "Sensor",
    "Speaker",
    "Temperature",
    "TofSensor",
]
