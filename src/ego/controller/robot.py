"""Webots' ``Robot`` (and the old ``DifferentialWheels``) for the e-puck, over ego's core Robot."""

from __future__ import annotations

import logging
import math
from typing import ClassVar, TypeVar

from ego.controller.devices import (
    LED,
    Accelerometer,
    Camera,
    Device,
    DistanceSensor,
    LightSensor,
    Motor,
    PositionSensor,
    encoder_steps,
    view_class,
    whole_steps,
)
from ego.default_robot import current_context
from ego.errors import UnknownDeviceError
from ego.robot import Robot as CoreRobot
from ego.runtime import RunOptions

__all__ = ["DifferentialWheels", "Robot"]

log = logging.getLogger(__name__)

_D = TypeVar("_D", bound=Device)


class Robot:
    """The e-puck as a Webots controller sees it.

    >>> from controller import Robot                     # doctest: +SKIP
    >>> robot = Robot()
    >>> ps0 = robot.getDevice("ps0"); ps0.enable(32)
    >>> while robot.step(32) != -1:
    ...     print(ps0.getValue())
    """

    MODE_SIMULATION: ClassVar[int] = 0
    MODE_CROSS_COMPILATION: ClassVar[int] = 1
    MODE_REMOTE_CONTROL: ClassVar[int] = 2

    def __init__(self, *, options: RunOptions | None = None) -> None:
        """``options`` None: the current face context's (what ``ego run`` was given)."""
        if options is None:
            options = current_context().options
        self._options = options
        self._core = CoreRobot(options.port, firmware=options.firmware, seed=options.seed)
        self._devices: dict[str, Device] = {}
        self._motors: list[Motor] = []
        for callback in options.on_robot:
            callback(self._core)

    @property
    def core(self) -> CoreRobot:
        """The ego Robot underneath, for what Webots' API does not cover."""
        return self._core

    def step(self, duration: int) -> int:
        """One time step of ``duration`` ms; -1 when the run ends or the link is lost."""
        if self._options.time_is_up(self._core.time_s):
            self._core.close()
            return -1
        result = self._core.step(duration)
        for motor in self._motors:
            motor.step_update()
        return result

    def getDevice(self, name: str) -> Device:
        """The device called ``name`` (``ps0``, ``left wheel motor``, ``camera``...)."""
        device = self._devices.get(name)
        if device is None:
            cls = view_class(name) if name in self._core.device_names else None
            if cls is None:
                raise UnknownDeviceError(
                    f"no device named {name!r}; valid names: {', '.join(self._device_names())}"
                )
            if cls is Motor:
                motor = Motor(self._core, name, basic_time_step_ms=self.getBasicTimeStep())
                self._motors.append(motor)
                device = motor
            else:
                device = cls(self._core, name)
            self._devices[name] = device
        return device

    def _device_names(self, cls: type[Device] = Device) -> list[str]:
        """The names ``getDevice`` serves under the connected firmware, of class ``cls``."""
        return [
            name
            for name in self._core.device_names
            if (found := view_class(name)) is not None and issubclass(found, cls)
        ]

    def _typed(self, name: str, cls: type[_D]) -> _D:
        device = self.getDevice(name)
        if not isinstance(device, cls):
            raise UnknownDeviceError(
                f"{name!r} is a {type(device).__name__}, not a {cls.__name__}; valid names: "
                f"{', '.join(self._device_names(cls))}"
            )
        return device

    # Deprecated getters of older Webots versions, still found in e-puck controllers.
    def getDistanceSensor(self, name: str) -> DistanceSensor:
        return self._typed(name, DistanceSensor)

    def getLightSensor(self, name: str) -> LightSensor:
        return self._typed(name, LightSensor)

    def getMotor(self, name: str) -> Motor:
        return self._typed(name, Motor)

    def getLED(self, name: str) -> LED:
        return self._typed(name, LED)

    def getCamera(self, name: str) -> Camera:
        return self._typed(name, Camera)

    def getAccelerometer(self, name: str) -> Accelerometer:
        return self._typed(name, Accelerometer)

    def getPositionSensor(self, name: str) -> PositionSensor:
        return self._typed(name, PositionSensor)

    def getBasicTimeStep(self) -> float:
        return float(self._options.basic_time_step_ms)

    def getTime(self) -> float:
        """Controller time in seconds."""
        return self._core.time_s

    def getName(self) -> str:
        return "e-puck"

    def getMode(self) -> int:
        """Cross-compilation on the robot; remote control over tcp:// or udp://."""
        if self._core.remote:
            return self.MODE_REMOTE_CONTROL
        return self.MODE_CROSS_COMPILATION

    # The battery, where the firmware serves it (docs/protocol.md, quirk "b": GCtronic's
    # stock firmware only). On Webots' firmware enabling it raises UnsupportedDeviceError.
    def batterySensorEnable(self, samplingPeriod: int) -> None:
        self._core.battery.enable(samplingPeriod)

    def batterySensorDisable(self) -> None:
        self._core.battery.disable()

    def batterySensorGetSamplingPeriod(self) -> int:
        return self._core.battery.sampling_period() or 0

    def batterySensorGetValue(self) -> float:
        """The raw ADC count on an e-puck rev 1.3, else the low-battery flag (1: fine).

        Webots gives the battery's energy in joules, which no e-puck firmware measures;
        NaN before the first sample, as Webots returns before its first step.
        """
        if not self._core.battery.has_values:
            return math.nan
        return self._core.battery.value

    def cleanup(self) -> None:
        """Stop the robot and close the link (also done at exit)."""
        self._core.close()


class DifferentialWheels(Robot):
    """Webots' old e-puck base class: wheel speeds in steps/s (1 step = 0.00628 rad)."""

    def setSpeed(self, left: float, right: float) -> None:
        self._core.motors.set_speed(left, right)

    def getLeftSpeed(self) -> float:
        return float(self._core.motors.speed[0])

    def getRightSpeed(self) -> float:
        return float(self._core.motors.speed[1])

    def getMaxSpeed(self) -> float:
        return 1000.0

    def getSpeedUnit(self) -> float:
        return 0.00628

    def enableEncoders(self, ms: int) -> None:
        self._core.encoders.enable(ms)

    def disableEncoders(self) -> None:
        self._core.encoders.disable()

    def getEncodersSamplingPeriod(self) -> int:
        return self._core.encoders.sampling_period() or 0

    def getLeftEncoder(self) -> float:
        return self._encoder(0)

    def getRightEncoder(self) -> float:
        return self._encoder(1)

    def _encoder(self, side: int) -> float:
        return encoder_steps(self._core, side)

    def setEncoders(self, left: float, right: float) -> None:
        self._core.encoders.set(whole_steps(left), whole_steps(right))
