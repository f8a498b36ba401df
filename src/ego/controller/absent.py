"""The classes of Webots' ``controller`` module for devices the e-puck does not have.

Every class a Webots controller may import exists, so that ``from controller import GPS``
never fails; a device of one is never found on the robot: ``getDevice("gps")`` prints
Webots' own warning and returns None, and constructing one by name (``GPS("gps")``)
raises UnknownDeviceError listing the names the robot has. The supervisor API likewise
exists, and says that a real robot has no simulation to supervise.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, NoReturn

from ego.controller.devices import Device
from ego.controller.node_types import NODE_TYPES
from ego.errors import UnsupportedDeviceError

if TYPE_CHECKING:
    from ego.core.ground_truth import GroundTruth
    from ego.core.robot import Robot as CoreRobot

__all__ = [
    "GPS",
    "Altimeter",
    "Brake",
    "CameraRecognitionObject",
    "Compass",
    "Connector",
    "Display",
    "Field",
    "InertialUnit",
    "Lidar",
    "Node",
    "Pen",
    "Radar",
    "RangeFinder",
    "Skin",
    "TouchSensor",
    "VacuumGripper",
]


class _GroundTruth(Device):
    """A device the real e-puck lacks, read from the emulator's world where it declares it
    (localisation labs add a GPS or a compass to the e-puck in Webots)."""

    def __init__(
        self, core: CoreRobot | str, name: str = "", *, strict: bool | None = None
    ) -> None:
        if isinstance(core, str):
            return  # made by name (Device.__new__)
        super().__init__(core, name, strict=strict)
        self._period = 0

    def _truth(self) -> GroundTruth:
        truth = self._core.ground_truth
        if truth is None:  # made only where the world declares it: a simulated robot
            raise UnsupportedDeviceError(f"{self._name!r}: a real robot has no ground truth")
        return truth

    def enable(self, samplingPeriod: int) -> None:
        self._period = int(samplingPeriod)

    def disable(self) -> None:
        self._period = 0

    def getSamplingPeriod(self) -> int:
        return self._period

    def getValues(self) -> list[float]:
        """GPS: x, y, z (m); Compass: north in the robot's frame. NaN while disabled."""
        if not self._period:
            return [math.nan] * 3
        pose = self._truth().pose()
        if pose is None:
            return [math.nan] * 3
        if isinstance(self, GPS):  # the centre, Webots' ENU frame (x east, y north, z up)
            return [pose.x_m, pose.y_m, 0.0]
        # North (+y) in the robot's frame (x forward, y left, z up), as Webots' Compass.
        return [math.sin(pose.theta_rad), math.cos(pose.theta_rad), 0.0]

    def getValue(self) -> float:
        """TouchSensor: 1.0 when the body touches a wall or a box (NaN while disabled)."""
        if not self._period:
            return math.nan
        world = self._truth().true_world
        return 1.0 if world is not None and world.touching() else 0.0

    value = property(lambda self: self.getValue())


#: The ground-truth devices a world file may declare, and their classes.
def ground_truth_class(name: str) -> type[Device] | None:
    return {"gps": GPS, "compass": Compass, "touch sensor": TouchSensor}.get(name)


class Altimeter(Device):
    """Webots' Altimeter; the e-puck has none."""

    _node_type = "ALTIMETER"


class Brake(Device):
    """Webots' Brake; the e-puck's wheels have none."""

    _node_type = "BRAKE"


class Compass(_GroundTruth):
    """Webots' Compass; the e-puck has none: on the emulator only (``--port sim``), when
    the world file declares one, it reads the emulated world's ground truth."""

    _node_type = "COMPASS"


class Connector(Device):
    """Webots' Connector; the e-puck has none."""

    _node_type = "CONNECTOR"


class Display(Device):
    """Webots' Display; the e-puck has none."""

    _node_type = "DISPLAY"


class GPS(_GroundTruth):
    """Webots' GPS; the e-puck has none: on the emulator only (``--port sim``), when
    the world file declares one, it reads the emulated world's ground truth."""

    _node_type = "GPS"


class InertialUnit(Device):
    """Webots' InertialUnit; the e-puck has none."""

    _node_type = "INERTIAL_UNIT"


class Lidar(Device):
    """Webots' Lidar; the e-puck has none."""

    _node_type = "LIDAR"


class Pen(Device):
    """Webots' Pen; the e-puck has none."""

    _node_type = "PEN"


class Radar(Device):
    """Webots' Radar; the e-puck has none."""

    _node_type = "RADAR"


class RangeFinder(Device):
    """Webots' RangeFinder; the e-puck has none."""

    _node_type = "RANGE_FINDER"


class Skin(Device):
    """Webots' Skin; the e-puck has none."""

    _node_type = "SKIN"


class TouchSensor(_GroundTruth):
    """Webots' TouchSensor; the e-puck has none: on the emulator only (``--port sim``), when
    the world file declares one, it reads the emulated world's ground truth."""

    _node_type = "TOUCH_SENSOR"


class VacuumGripper(Device):
    """Webots' VacuumGripper; the e-puck has none."""

    _node_type = "VACUUM_GRIPPER"


class CameraRecognitionObject:
    """What Webots' camera recognition returns; the e-puck's camera recognises nothing."""

    def __init__(self) -> None:
        self.id = 0
        self.position = [0.0, 0.0, 0.0]
        self.orientation = [0.0, 0.0, 1.0, 0.0]
        self.size = [0.0, 0.0]
        self.position_on_image = [0, 0]
        self.size_on_image = [0, 0]
        self.number_of_colors = 0
        self.colors: list[float] = []
        self.model = ""


def _no_simulation(what: str) -> NoReturn:
    raise UnsupportedDeviceError(
        f"{what} supervises a simulation, and a real e-puck has none to supervise"
    )


class Node:
    """Webots' scene-tree Node: a supervisor's, and there is no scene tree on a robot.
    Its type constants (``Node.DISTANCE_SENSOR``) are there, for ``getNodeType()``."""

    def __init__(self, *args: object, **kwargs: object) -> None:
        _no_simulation("Node")


for _number, _name in enumerate(NODE_TYPES):
    setattr(Node, _name, _number)


class Field:
    """Webots' scene-tree Field: a supervisor's, and there is no scene tree on a robot."""

    def __init__(self, *args: object, **kwargs: object) -> None:
        _no_simulation("Field")


class LidarPoint:
    """A point of Webots' Lidar cloud; the e-puck has no lidar, so none is ever made."""

    def __init__(self) -> None:
        self.x = self.y = self.z = 0.0
        self.layer_id = 0
        self.time = 0.0


class RadarTarget:
    """A target of Webots' Radar; the e-puck has no radar, so none is ever made."""

    def __init__(self) -> None:
        self.distance = self.received_power = self.speed = self.azimuth = 0.0


class Motion:
    """Webots' humanoid motion files (``.motion``): the e-puck has no joints to play them."""

    def __init__(self, *args: object, **kwargs: object) -> None:
        raise UnsupportedDeviceError("Motion plays joint motions, and the e-puck has no joints")
