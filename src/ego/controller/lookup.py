"""Webots' device lookup for the controller face's Robot: getDevice and its deprecated getters."""

from __future__ import annotations

import sys
from typing import TYPE_CHECKING

from ego.controller.accelerometer import Accelerometer
from ego.controller.camera import Camera, webots_camera_size
from ego.controller.compass import Compass
from ego.controller.device import Device, view_class
from ego.controller.distance_sensor import DistanceSensor
from ego.controller.emitter import Emitter
from ego.controller.gps import GPS
from ego.controller.gyro import Gyro
from ego.controller.led import LED
from ego.controller.light_sensor import LightSensor
from ego.controller.motor import Motor
from ego.controller.position_sensor import PositionSensor
from ego.controller.radio import RADIO_DEVICES, RobotRadio, radio_available
from ego.controller.receiver import Receiver
from ego.controller.speaker import Speaker
from ego.controller.touch_sensor import TouchSensor
from ego.errors import UnknownDeviceError

if TYPE_CHECKING:
    from ego.core.environment import Environment
    from ego.core.robot import Robot as CoreRobot
    from ego.faces.runtime import RunOptions

__all__ = ["DeviceLookup"]

#: The ground-truth devices a world file may declare (on the emulator), and their classes.
GROUND_TRUTH_CLASSES: dict[str, type[Device]] = {
    "gps": GPS, "compass": Compass, "touch sensor": TouchSensor
}  # fmt: skip


class DeviceLookup:
    """The part of :class:`ego.controller.Robot` that finds its devices by name: the base
    class of that Robot, whose constructor sets the attributes below."""

    _core: CoreRobot
    _options: RunOptions
    _devices: dict[str, Device]
    _motors: list[Motor]
    _environment: Environment
    _radio: RobotRadio

    def getName(self) -> str:
        """Webots' robot name: ``e-puck``, or a swarm robot's own (its Zenoh node's name,
        as each robot of a Webots swarm has its own name field)."""
        return str(getattr(self._core.channel, "robot", None) or "e-puck")

    def getBasicTimeStep(self) -> float:
        return float(self._options.basic_time_step_ms)

    def _ground_truth(self, name: str) -> bool:
        """Whether the emulator's world declares ``name`` (gps, compass, touch sensor)."""
        truth = self._core.ground_truth
        world = truth.true_world if truth is not None else None
        return world is not None and name in world.declared_devices()

    def getDevice(self, name: str) -> Device | None:
        """The device called ``name`` (``ps0``, ``left wheel motor``, ``camera``...).

        A name the e-puck has not (``gps``): Webots' warning on stderr and None, as in
        Webots; under ``ego run --strict``, UnknownDeviceError listing the valid names.
        """
        device = self._devices.get(name)
        if device is None:
            cls = view_class(name) if name in self._core.device_names else None
            if name in RADIO_DEVICES and radio_available(self._environment):
                cls = Emitter if name == "emitter" else Receiver
            if cls is None and self._ground_truth(name):
                cls = GROUND_TRUTH_CLASSES.get(name)
            if cls is None:
                if not self._options.strict:
                    print(
                        f'Device "{name}" was not found on robot "{self.getName()}"',
                        file=sys.stderr,
                    )
                    return None
                raise UnknownDeviceError(
                    f"no device named {name!r}; valid names: {', '.join(self._device_names())}"
                )
            if cls is Motor:
                motor = Motor(
                    self._core,
                    name,
                    basic_time_step_ms=self.getBasicTimeStep(),
                    strict=self._options.strict,
                )
                self._motors.append(motor)
                device = motor
            elif cls is Emitter or cls is Receiver:  # the two share the robot's one radio
                device = cls(self._core, name, strict=self._options.strict, radio=self._radio)
            else:
                device = cls(self._core, name, strict=self._options.strict)
                if cls is Camera:
                    webots_camera_size(self._core)
            self._devices[name] = device
        return device

    def _device_names(self, cls: type[Device] = Device) -> list[str]:
        """The names ``getDevice`` serves under the connected firmware, of class ``cls``."""
        return [
            name
            for name in self._core.device_names
            if (found := view_class(name)) is not None and issubclass(found, cls)
        ]

    def _deprecated(self, getter: str, name: str, cls: type[Device]) -> Device | None:
        """Webots' deprecated typed getters: its notice, then ``getDevice`` (Webots' warning
        and None for a name the e-puck has not; the device whatever its class, as Webots
        does not check it). Under ``--strict`` a device of another class is refused."""
        print(
            f"DEPRECATION: Robot.{getter} is deprecated, please use Robot.getDevice instead.",
            file=sys.stderr,
        )
        device = self.getDevice(name)
        if self._options.strict and device is not None and not isinstance(device, cls):
            raise UnknownDeviceError(
                f"{name!r} is a {type(device).__name__}, not a {cls.__name__}; valid names "
                f"for a {cls.__name__}: {', '.join(self._device_names(cls)) or 'none'}"
            )
        return device

    def getDistanceSensor(self, name: str) -> DistanceSensor | None:
        return self._deprecated("getDistanceSensor", name, DistanceSensor)  # type: ignore[return-value]

    def getLightSensor(self, name: str) -> LightSensor | None:
        return self._deprecated("getLightSensor", name, LightSensor)  # type: ignore[return-value]

    def getMotor(self, name: str) -> Motor | None:
        return self._deprecated("getMotor", name, Motor)  # type: ignore[return-value]

    def getLED(self, name: str) -> LED | None:
        return self._deprecated("getLed", name, LED)  # type: ignore[return-value]

    def getCamera(self, name: str) -> Camera | None:
        return self._deprecated("getCamera", name, Camera)  # type: ignore[return-value]

    def getAccelerometer(self, name: str) -> Accelerometer | None:
        return self._deprecated("getAccelerometer", name, Accelerometer)  # type: ignore[return-value]

    def getPositionSensor(self, name: str) -> PositionSensor | None:
        return self._deprecated("getPositionSensor", name, PositionSensor)  # type: ignore[return-value]

    def getEmitter(self, name: str) -> Emitter | None:
        """The radio emitter (see ego.controller.radio), deprecated as in Webots."""
        return self._deprecated("getEmitter", name, Emitter)  # type: ignore[return-value]

    def getReceiver(self, name: str) -> Receiver | None:
        """The radio receiver (see ego.controller.radio), deprecated as in Webots."""
        return self._deprecated("getReceiver", name, Receiver)  # type: ignore[return-value]

    def getGyro(self, name: str) -> Gyro | None:
        return self._deprecated("getGyro", name, Gyro)  # type: ignore[return-value]

    def getSpeaker(self, name: str) -> Speaker | None:
        return self._deprecated("getSpeaker", name, Speaker)  # type: ignore[return-value]

    # Deprecated getters of devices the e-puck has not: the same notice, then None.
    def _absent_getter(self, name: str) -> None:
        return self.getDevice(name)  # type: ignore[return-value]

    getGPS = getCompass = getInertialUnit = getTouchSensor = _absent_getter
    getDisplay = getPen = getLidar = _absent_getter
    getRangeFinder = getRadar = getConnector = getBrake = getAltimeter = _absent_getter
    getSkin = getVacuumGripper = _absent_getter

    def getNumberOfDevices(self) -> int:
        return len(self._device_names())

    def getDeviceByIndex(self, index: int) -> Device | None:
        names = self._device_names()
        if not 0 <= index < len(names):
            raise UnknownDeviceError(f"device index {index} is outside 0..{len(names) - 1}")
        return self.getDevice(names[index])
