"""Webots' ``Robot`` (and the old ``DifferentialWheels``) for the e-puck, over ego's core Robot."""

from __future__ import annotations

import logging
import math
import sys
import time
from typing import ClassVar

from ego.controller.device import Device
from ego.controller.joystick import Joystick
from ego.controller.keyboard import Keyboard
from ego.controller.lookup import DeviceLookup
from ego.controller.motor import Motor
from ego.controller.mouse import Mouse
from ego.controller.position_sensor import encoder_steps, whole_steps
from ego.controller.radio import RobotRadio
from ego.controller.step_overlap import StepOverlap
from ego.core.robot import Robot as CoreRobot
from ego.errors import EgoError, UnsupportedDeviceError
from ego.faces.default_robot import current_context, ended_reason
from ego.faces.runtime import RunOptions

__all__ = ["DifferentialWheels", "Robot"]

log = logging.getLogger(__name__)

#: The ``model`` field of Webots' E-puck PROTO (projects/robots/gctronic/e-puck).
EPUCK_MODEL = "GCtronic e-puck"
#: What Webots prints for a second ``Robot()`` in one controller process.
ONE_ROBOT_ONLY = "Error: only one Robot instance can be created per controller process."


class Robot(DeviceLookup):
    """The e-puck as a Webots controller sees it.

    >>> from controller import Robot                     # doctest: +SKIP
    >>> robot = Robot()
    >>> ps0 = robot.getDevice("ps0"); ps0.enable(32)
    >>> while robot.step(32) != -1:
    ...     print(ps0.getValue())
    """

    _core: CoreRobot
    #: Plain attributes, as in Webots' Robot (a controller may replace them).
    keyboard: Keyboard
    mouse: Mouse
    joystick: Joystick
    core: CoreRobot
    MODE_SIMULATION: ClassVar[int] = 0
    MODE_CROSS_COMPILATION: ClassVar[int] = 1
    MODE_REMOTE_CONTROL: ClassVar[int] = 2

    def __init__(self, *, options: RunOptions | None = None) -> None:
        """``options`` None: the current face context's (what ``ego run`` was given)."""
        context = current_context()
        first = context.webots_robot
        if isinstance(first, Robot) and not first._core.closed:
            # Webots allows one Robot a process and says so; the second one here is the
            # same robot under another name (in Webots it would be unusable).
            if (options or context.options).strict:
                raise EgoError("only one Robot instance can be created per controller process")
            print(ONE_ROBOT_ONLY, file=sys.stderr)
            self.__dict__ = first.__dict__
            return
        if options is None:
            options = context.options
        self._options = options
        self._custom_data = ""
        # Plain attributes, as Webots' Robot has them: a controller may replace them.
        self.keyboard = Keyboard(0)
        self.mouse = Mouse(0)
        self.joystick = Joystick(0)
        self._core = context.new_robot(options=options)
        self._environment = context.environment
        #: The run's end: a controller going on after -1 is ended as Webots ends it.
        self._termination = context.termination
        #: The robot's radio (its emitter's and receiver's), opened at first use.
        self._radio = RobotRadio(self._core, context.environment)
        #: The ego Robot underneath, for what Webots' API does not cover (a plain
        #: attribute: ego reads its own ``_core``, so a subclass may reuse the name).
        self.core = self._core
        self._devices: dict[str, Device] = {}
        self._motors: list[Motor] = []
        # The keyboard's reader thread ends with the robot, however the run closes it;
        # so does a step in flight between stepBegin and stepEnd.
        self._core.add_closer(self._stop_inputs)
        self._overlap = StepOverlap(self.step)
        self._core.add_closer(self._overlap.close)
        context.webots_robot = self
        for callback in options.on_robot:
            callback(self._core)

    def step(self, duration: int | None = None) -> int:
        """One time step of ``duration`` ms (the basic time step if None); -1 when the run
        ends or the link is lost. A controller that goes on stepping is ended about one
        second of real time later, as Webots ends it (ego.faces.termination)."""
        if duration is None:
            duration = int(self.getBasicTimeStep())
        if self._core.closed and self._termination.ended_at is not None:
            return self._termination.ended("")  # the grace after the first -1 runs
        if self._options.time_is_up(self._core.time_s):
            self._core.close()
            return self._termination.ended(self._options.time_up_reason())
        result = self._core.step(duration)
        if result == -1:
            return self._termination.ended(ended_reason(self._core))
        for motor in self._motors:
            motor.step_update()
        return result

    def getTime(self) -> float:
        """Controller time in seconds."""
        return self._core.time_s

    def getModel(self) -> str:
        """The model field of Webots' E-puck PROTO, which controllers branch on."""
        return EPUCK_MODEL

    def getCustomData(self) -> str:
        return self._custom_data

    def setCustomData(self, data: str) -> None:
        self._custom_data = str(data)

    def getKeyboard(self) -> Keyboard:
        """The terminal's keyboard (see ego.controller.keyboard)."""
        return self.keyboard

    def getMouse(self) -> Mouse:
        return self.mouse

    def getJoystick(self) -> Joystick:
        return self.joystick

    EVENT_QUIT = -1
    EVENT_NO_EVENT = 0
    EVENT_MOUSE_CLICK = 1
    EVENT_MOUSE_MOVE = 2
    EVENT_KEYBOARD = 4
    EVENT_JOYSTICK_BUTTON = 8
    EVENT_JOYSTICK_AXIS = 16
    EVENT_JOYSTICK_POV = 32

    def stepBegin(self, duration: int | None = None) -> int:
        """Start a step and return at once: the exchange with the robot runs while the
        controller computes, until :meth:`stepEnd` (ego.controller.step_overlap)."""
        if self._core.closed and self._termination.ended_at is not None:
            return self._termination.ended("")
        self._overlap.begin(duration)
        return 0

    def stepEnd(self) -> int:
        """Wait for the step :meth:`stepBegin` started; its result (-1: the run ended)."""
        return self._overlap.end()

    def waitForUserInputEvent(self, event_type: int, timeout: int) -> int:
        """Wait up to ``timeout`` ms for a key (the only input a robot has); the event."""
        if event_type & self.EVENT_KEYBOARD and self.keyboard.getSamplingPeriod() > 0:
            end = time.monotonic() + timeout / 1000.0
            while time.monotonic() < end:
                if not self.keyboard.empty():
                    return self.EVENT_KEYBOARD
                time.sleep(0.005)
        else:
            time.sleep(timeout / 1000.0)
        return self.EVENT_NO_EVENT

    def setMode(self, mode: int, arg: str) -> None:
        """Webots switches to remote control here; ego chooses by port: ``ego run --port
        tcp://robot:4242`` drives a robot served by ``ego serve``."""
        if mode != self.getMode():
            raise UnsupportedDeviceError(
                "the mode follows the port: run with --port tcp://ROBOT:4242 (ego serve on "
                "the robot) for remote control, or on the robot itself for cross-compilation"
            )

    def wwiSendText(self, text: str) -> None:
        """A robot window's channel: a real robot has no window, so nothing listens."""

    def wwiReceiveText(self) -> str | None:
        return None

    def getUrdf(self, prefix: str = "") -> str:
        raise UnsupportedDeviceError(
            "the e-puck's URDF is Webots' to export: there is no world here"
        )

    def getSynchronization(self) -> bool:
        """Always: the controller's step paces the robot, as a synchronised Webots robot."""
        return True

    def getSupervisor(self) -> bool:
        return False

    def getProjectPath(self) -> str:
        return ""

    def getWorldPath(self) -> str:
        return ""

    # The Python properties of Webots' own module.
    time = property(lambda self: self.getTime())
    name = property(lambda self: self.getName())
    model = property(lambda self: self.getModel())
    basic_time_step = property(lambda self: self.getBasicTimeStep())
    custom_data = property(lambda self: self.getCustomData(), lambda self, v: self.setCustomData(v))
    number_of_devices = property(lambda self: self.getNumberOfDevices())
    synchronization = property(lambda self: self.getSynchronization())
    supervisor = property(lambda self: self.getSupervisor())
    mode = property(lambda self: self.getMode())
    project_path = property(lambda self: self.getProjectPath())
    world_path = property(lambda self: self.getWorldPath())
    battery_sensor_sampling_period = property(
        lambda self: self.batterySensorGetSamplingPeriod(),
        lambda self, period: self.batterySensorEnable(
            int(self.getBasicTimeStep()) if period is None else period
        ),
    )

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

    def _stop_inputs(self) -> None:
        self.keyboard.disable()

    def cleanup(self) -> None:
        """Stop the robot and close the link (also done at exit); the terminal back."""
        self.keyboard.disable()
        self._core.close()


class DifferentialWheels(Robot):
    """Webots' old e-puck base class: wheel speeds in steps/s (1 step = 0.00628 rad)."""

    def setSpeed(self, left: float, right: float) -> None:
        """Steps/s; beyond +-1000 clamped with a warning, as Webots did (strict: refused)."""
        if not self._options.strict:
            left, right = (_clamp_speed(v) for v in (left, right))
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


def _clamp_speed(speed: float) -> float:
    """A DifferentialWheels speed within +-1000 steps/s, with Webots' warning beyond."""
    if isinstance(speed, int | float) and not isinstance(speed, bool) and abs(speed) > 1000:
        print(
            f"Warning: the requested speed {speed:g} exceeds the maximum speed 1000.",
            file=sys.stderr,
        )
        return math.copysign(1000, speed)
    return speed
