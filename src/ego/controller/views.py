"""The Webots class of each device name of the robot's table."""

from __future__ import annotations

from ego.controller.accelerometer import Accelerometer
from ego.controller.camera import Camera
from ego.controller.device import Device
from ego.controller.distance_sensor import DistanceSensor
from ego.controller.gyro import Gyro
from ego.controller.led import LED
from ego.controller.light_sensor import LightSensor
from ego.controller.motor import Motor
from ego.controller.position_sensor import PositionSensor
from ego.controller.speaker import Speaker
from ego.devices.table import find

__all__ = ["view_class"]

#: The view class of each kind of :mod:`ego.devices.table` that Webots' e-puck has.
_VIEWS: dict[str, type[Device]] = {
    "DistanceSensor": DistanceSensor,
    "LightSensor": LightSensor,
    "LED": LED,
    "Motor": Motor,
    "PositionSensor": PositionSensor,
    "Accelerometer": Accelerometer,
    "Camera": Camera,
    "Gyro": Gyro,
    "Speaker": Speaker,
}


def view_class(name: str) -> type[Device] | None:
    """The Webots class of a device name; None for ego's names Webots has no device for (mics)."""
    found = find(name)
    if found is None or not found.webots_device:
        return None
    return _VIEWS.get(found.kind)


def ground_truth_class(name: str) -> type[Device] | None:
    """The class of a ground-truth device a world file may declare (gps, compass, touch)."""
    from ego.controller.compass import Compass
    from ego.controller.gps import GPS
    from ego.controller.touch_sensor import TouchSensor

    return {"gps": GPS, "compass": Compass, "touch sensor": TouchSensor}.get(name)
