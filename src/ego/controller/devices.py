"""Webots' device classes (camelCase, Webots units) as thin views of ego's device families."""

from __future__ import annotations

import logging
import math
import numbers
import sys
from typing import TYPE_CHECKING, ClassVar

import numpy as np
import numpy.typing as npt

from ego.controller.node_types import node_type
from ego.devices.base import ArraySensor, Sampled
from ego.devices.motors import rad_s_to_steps, steps_to_rad_s
from ego.devices.position_control import position_speed
from ego.devices.table import find, spec
from ego.errors import EgoError, OutOfRangeError, UnknownDeviceError, UnsupportedDeviceError
from ego.faces.webots_model import webots_model

if TYPE_CHECKING:
    from ego.core.robot import Robot as CoreRobot

__all__ = [
    "LED",
    "Accelerometer",
    "Camera",
    "Device",
    "DistanceSensor",
    "Gyro",
    "LightSensor",
    "Motor",
    "PositionSensor",
    "Speaker",
    "encoder_steps",
    "view_class",
    "webots_camera_size",
    "whole_steps",
]

log = logging.getLogger(__name__)

# Webots' E-puck PROTO (projects/robots/gctronic/e-puck/protos), what its devices report.
#: E-puckDistanceSensor's lookupTable: distance (m), value, noise; rows flattened.
PROXIMITY_TABLE = (
    0, 4095, 0.002, 0.005, 2133.33, 0.003, 0.01, 1465.73, 0.007, 0.015, 601.46, 0.0406,
    0.02, 383.84, 0.01472, 0.03, 234.93, 0.0241, 0.04, 158.03, 0.0287, 0.05, 120, 0.04225,
    0.06, 104.09, 0.03065, 0.07, 67.19, 0.04897,
)  # fmt: skip
PROXIMITY_APERTURE_RAD = 0.1
#: The light sensors' lookupTable.
LIGHT_TABLE = (1, 4095, 0.01, 2, 0, 0.01)
#: The accelerometer's lookupTable.
ACCELEROMETER_TABLE = (-100, -100, 0.003, 100, 100, 0.003)
#: The camera's near plane.
CAMERA_NEAR_M = 0.0055
#: The PROTO's camera_width and camera_height: what a Webots controller expects.
WEBOTS_CAMERA_SIZE = (52, 39)

_NAN = float("nan")


def _view_base(cls: type[Device]) -> type[Device]:
    """The class of ego's own that ``cls`` is or derives from (a user's ``WheelMotor``
    subclass of ``Motor`` gives ``Motor``)."""
    for klass in cls.__mro__:
        if klass.__module__.startswith("ego.controller") and issubclass(klass, Device):
            return klass
    return Device


def _by_name(cls: type[Device], name: str) -> Device:
    """The device ``name`` of the run's Robot as a ``cls`` (Webots' R2023b constructors).

    ``cls`` may be ego's class of the device, one of its bases (``Device("ps0")``), or a
    subclass a controller wrote (``class WheelMotor(Motor)``), as Webots' ``Device(name)``
    accepts any: a subclass gets an object of its own that shares the device's state,
    as two Webots objects share one device tag.
    """
    from ego.faces.default_robot import current_context

    robot = current_context().webots_robot
    if robot is None or robot._core.closed:  # type: ignore[attr-defined]
        raise EgoError(f"{cls.__name__}({name!r}): create the Robot() first, as Webots requires")
    device = robot.getDevice(name)  # type: ignore[attr-defined]
    if isinstance(device, cls):
        return device
    if device is not None and issubclass(cls, type(device)):
        view = object.__new__(cls)
        view.__dict__ = device.__dict__  # one device, two names for it
        return view
    base = _view_base(cls)
    valid = robot._device_names(base)  # type: ignore[attr-defined]
    what = "no device" if device is None else f"a {type(device).__name__}"
    raise UnknownDeviceError(
        f"{name!r} is {what}, not a {base.__name__}; valid names for a "
        f"{base.__name__}: {', '.join(valid) or 'none on this robot'}"
    )


def webots_camera_size(core: CoreRobot) -> None:
    """Give ``core``'s camera the size a Webots controller expects: the run's
    ``--camera WxH``, else the emulator's world's (its camera_width/camera_height, as a
    Webots world sets them), else Webots' e-puck's 52x39 (the E-GO face keeps 640x480)."""
    from ego.faces.default_robot import current_context

    truth = core.ground_truth
    world = truth.true_world if truth is not None else None
    size = (
        current_context().options.camera_size
        or (world.camera_size if world is not None else None)
        or WEBOTS_CAMERA_SIZE
    )
    if (core.camera.width, core.camera.height) != size:
        core.camera.set_size(*size)


def _sibling(device: Device, name: str) -> Device | None:
    """Another device of the same robot, as its Webots Robot serves it."""
    from ego.faces.default_robot import current_context

    robot = current_context().webots_robot
    if robot is not None and robot._core is device._core:  # type: ignore[attr-defined]
        found = robot.getDevice(name)  # type: ignore[attr-defined]
        return found if isinstance(found, Device) else None
    view = view_class(name)
    return view(device._core, name, strict=device._strict) if view is not None else None


def _is_real(value: object) -> bool:
    """A real number (numpy's too), neither a bool nor NaN."""
    return (
        not isinstance(value, bool)
        and isinstance(value, numbers.Real)
        and not math.isnan(float(value))
    )


class Device:
    """A named device of the robot (Webots' ``Device``).

    ``Motor("left wheel motor")``, Webots' constructor by name since R2023b, gives the
    device of that name of the run's one ``Robot()``.
    """

    def __new__(cls, *args: object, **kwargs: object) -> Device:
        # By name (a str first, as Webots' Device(name)); ego's faces pass the core Robot.
        if args and isinstance(args[0], str):
            return _by_name(cls, args[0])
        return super().__new__(cls)

    def __init__(
        self, core: CoreRobot | str, name: str = "", *, strict: bool | None = None
    ) -> None:
        """``strict``: refuse what Webots lets through (``ego run --strict``); None: as the
        current run was asked."""
        if isinstance(core, str):
            return  # made by name (__new__): the robot's own device, already set up
        if strict is None:
            from ego.faces.default_robot import current_context

            strict = current_context().options.strict
        self._core = core
        self._name = name
        self._strict = strict

    def getName(self) -> str:
        return self._name

    def getModel(self) -> str:
        return "e-puck"

    #: The Webots node of a device the table does not hold (a ground-truth GPS...).
    _node_type = "NO_NODE"

    def getNodeType(self) -> int:
        """Webots' number for this device's node (``Node.DISTANCE_SENSOR``...): the device
        table's node type for the robot's own devices."""
        row = find(self._name)
        return node_type(row.kind if row is not None else self._node_type)

    name = property(lambda self: self.getName())
    model = property(lambda self: self.getModel())
    node_type = property(lambda self: self.getNodeType())

    def __repr__(self) -> str:
        return f"<{type(self).__name__} {self._name!r}>"


def _basic_time_step_ms() -> int:
    from ego.faces.default_robot import current_context

    return int(current_context().options.basic_time_step_ms)


class Sensor(Device):
    """``enable(ms)``, ``disable()``, ``getSamplingPeriod()`` of one member of a family
    (Webots' ``Sensor``, the base of every sensor class).

    Made by name, as ``DistanceSensor("ps0")`` or a subclass of it, a sensor is enabled
    at once, at ``sampling_period`` or else the basic time step (0 leaves it off), as
    Webots' ``Sensor.__init__`` does.
    """

    def __init__(
        self,
        core: CoreRobot | str,
        name: str | int | None = "",
        sampling_period: int | None = None,
        *,
        strict: bool | None = None,
    ) -> None:
        if isinstance(core, str):  # by name: (name, sampling_period=None), as Webots'
            period = name if isinstance(name, int) else sampling_period
            self.sampling_period = _basic_time_step_ms() if period is None else period
            return
        super().__init__(core, str(name), strict=strict)

    def _family(self) -> Sampled:
        family = self._core.device(self._name)
        assert isinstance(family, Sampled)
        return family

    def enable(self, samplingPeriod: int) -> None:
        self._family().enable(samplingPeriod, [self._name])

    def disable(self) -> None:
        self._family().disable([self._name])

    def getSamplingPeriod(self) -> int:
        """The period in ms, 0 when disabled (Webots' convention)."""
        return self._family().sampling_period(self._name) or 0

    #: Webots' property: reading gives the period (0: off); setting enables (0, None: off).
    sampling_period = property(
        lambda self: self.getSamplingPeriod(),
        lambda self, period: self.enable(period) if period else self.disable(),
    )

    def _readable(self) -> bool:
        family = self._family()
        return family.sampling_period(self._name) is not None and family.has_values


class _ValueSensor(Sensor):
    """A sensor giving one raw value a step through its lookup table (``value``)."""

    #: Webots' lookupTable of this kind of sensor in the E-puck PROTO.
    _table: tuple[float, ...] = ()
    #: The family serving this sensor, found at the first read (it never changes).
    _array: ArraySensor | None = None

    def _array_family(self) -> ArraySensor:
        array = self._array
        if array is None:
            family = self._family()
            assert isinstance(family, ArraySensor)
            array = self._array = family
        return array

    def getValue(self) -> float:
        """The reading as the robot gives it (the e-puck2's tof too: Webots' own remote
        control hands the robot's millimetres to getValue unchanged)."""
        array = self._array_family()
        return array.reading(self._name)

    def getLookupTable(self) -> list[float]:
        """Webots' table (distance m, value, noise per row), flattened: the family's own
        where Webots' model gives this device another (the e-puck2's ``tof``)."""
        own = webots_model(self._array_family()).lookup
        return list(self._table if own is None else own)

    value = property(lambda self: self.getValue())
    lookup_table = property(lambda self: self.getLookupTable())


class DistanceSensor(_ValueSensor):
    """ps0..ps9 proximity and gs0..gs2 floor sensors: raw values, as Webots' e-puck gives."""

    _table = PROXIMITY_TABLE
    GENERIC = 0
    INFRA_RED = 1
    SONAR = 2
    LASER = 3

    _TYPES: ClassVar[dict[str, int]] = {
        "generic": GENERIC, "infra-red": INFRA_RED, "sonar": SONAR, "laser": LASER
    }  # fmt: skip

    def getMinValue(self) -> float:
        """The table's smallest value, as Webots gives it."""
        return min(self.getLookupTable()[1::3])

    def getMaxValue(self) -> float:
        return max(self.getLookupTable()[1::3])

    def getAperture(self) -> float:
        own = webots_model(self._array_family()).aperture_rad
        return PROXIMITY_APERTURE_RAD if own is None else own

    def getType(self) -> int:
        own = webots_model(self._array_family()).sensor_type
        return self.INFRA_RED if own is None else self._TYPES[own]

    min_value = property(lambda self: self.getMinValue())
    max_value = property(lambda self: self.getMaxValue())
    aperture = property(lambda self: self.getAperture())
    type = property(lambda self: self.getType())


class LightSensor(_ValueSensor):
    """ls0..ls7: 0..4095, lower is brighter (the e-puck's own convention)."""

    _table = LIGHT_TABLE


class Accelerometer(Sensor):
    def getLookupTable(self) -> list[float]:
        return list(ACCELEROMETER_TABLE)

    def getValues(self) -> list[float]:
        """x, y, z in m/s^2 (NaN while not enabled)."""
        if not self._readable():
            return [_NAN, _NAN, _NAN]
        return list(self._core.accelerometer.acceleration_mps2)

    value = property(lambda self: self.getValues())
    lookup_table = property(lambda self: self.getLookupTable())


def whole_steps(value: float) -> int:
    """A finite float rounded to whole steps (the C API passes doubles); anything else as
    it is, so that the core refuses it with its own typed error (NaN, a string...)."""
    if isinstance(value, float) and math.isfinite(value):
        return round(value)
    return value  # type: ignore[return-value]  # not an int: the core's check refuses it


def encoder_steps(core: CoreRobot, side: int) -> float:
    """A wheel's step count, NaN unless the encoders are enabled and sampled."""
    encoders = core.encoders
    return float(encoders.values[side]) if encoders.enabled and encoders.has_values else _NAN


class PositionSensor(Sensor):
    """A wheel's step counter as an angle in radians."""

    ROTATIONAL = 0
    LINEAR = 1

    def getType(self) -> int:
        return self.ROTATIONAL

    def getMotor(self) -> Device | None:
        """The wheel's motor (``left wheel sensor`` -> ``left wheel motor``)."""
        return _sibling(self, self._name.replace("sensor", "motor"))

    def getBrake(self) -> None:
        """None: the e-puck's wheels have no brake device."""
        return None

    def getValue(self) -> float:
        if not self._readable():
            return _NAN
        return self._core.encoders.radians[spec(self._name).index]

    value = property(lambda self: self.getValue())
    type = property(lambda self: self.getType())
    motor = property(lambda self: self.getMotor())
    brake = property(lambda self: self.getBrake())


class Motor(Device):
    """A wheel motor. ``setPosition(float('inf'))`` then ``setVelocity(rad/s)``, max 6.28.

    A finite ``setPosition`` drives the wheel to that angle (rad) at the set velocity,
    using the step counters, as Webots' position control does.
    """

    def __init__(
        self,
        core: CoreRobot | str,
        name: str = "",
        *,
        basic_time_step_ms: float | None = None,
        strict: bool | None = None,
    ) -> None:
        if isinstance(core, str):
            return  # made by name: the robot's own motor (Device.__new__)
        super().__init__(core, name, strict=strict)
        self._side = spec(name).index
        #: The encoders' sampling period when position control enables them (ms); None:
        #: the current face context's basic time step.
        self._period_ms = basic_time_step_ms
        self._velocity = self._drivable_rad_s()
        #: Whether the firmware's clamp below the model's maxVelocity was told (once).
        self._told_clamp = False
        self._target = 0.0  # Webots' default: position control towards 0 rad
        self._acceleration = -1.0
        #: The speed (rad/s) sent last, for the acceleration ramp.
        self._sent_rad_s = 0.0

    ROTATIONAL = 0
    LINEAR = 1

    def getMaxVelocity(self) -> float:
        """The model's maxVelocity (Webots' e-puck: 6.28 rad/s; e-puck2: 7.536)."""
        model = self._core.channel.profile.model_max_velocity_rad_s
        return self._drivable_rad_s() if model is None else model

    def _drivable_rad_s(self) -> float:
        """The fastest the firmware drives the wheel (e-puck2: 1100 steps/s, 6.91 rad/s)."""
        return steps_to_rad_s(self._core.channel.profile.max_speed_steps)

    def getType(self) -> int:
        return self.ROTATIONAL

    def getMinPosition(self) -> float:
        """0: no limit, as Webots says of a wheel (minPosition = maxPosition = 0)."""
        return 0.0

    def getMaxPosition(self) -> float:
        return 0.0

    def getPositionSensor(self) -> Device | None:
        """The wheel's position sensor (``left wheel motor`` -> ``left wheel sensor``)."""
        return _sibling(self, self._name.replace("motor", "sensor"))

    def getBrake(self) -> None:
        """None: the e-puck's wheels have no brake device."""
        return None

    def setAcceleration(self, acceleration: float) -> None:
        """rad/s^2, -1 for none (Webots' default). The dsPIC has no ramp: the face ramps
        the speed it sends, step by step."""
        if not _is_real(acceleration) or (acceleration <= 0 and acceleration != -1):
            raise OutOfRangeError(f"acceleration {acceleration!r} must be positive, or -1 for none")
        self._acceleration = float(acceleration)

    def getAcceleration(self) -> float:
        return self._acceleration

    # Webots' properties, and only those: a controller may set any other attribute.
    target_velocity = property(
        lambda self: self.getVelocity(), lambda self, v: self.setVelocity(v)
    )
    target_position = property(
        lambda self: self.getTargetPosition(), lambda self, p: self.setPosition(p)
    )
    target_acceleration = property(
        lambda self: self.getAcceleration(), lambda self, a: self.setAcceleration(a)
    )
    max_velocity = property(lambda self: self.getMaxVelocity())
    max_position = property(lambda self: self.getMaxPosition())
    min_position = property(lambda self: self.getMinPosition())
    type = property(lambda self: self.getType())
    brake = property(lambda self: self.getBrake())
    position_sensor = property(lambda self: self.getPositionSensor())

    def getVelocity(self) -> float:
        return self._velocity

    def getTargetPosition(self) -> float:
        return self._target

    def setVelocity(self, velocity: float) -> None:
        """Wheel speed in rad/s within +-getMaxVelocity().

        As Webots: beyond it, clamped with Webots' warning; NaN reported and ignored.
        Under ``ego run --strict`` both are refused (OutOfRangeError), as ego's core does.
        """
        if isinstance(velocity, float) and math.isnan(velocity) and not self._strict:
            print(
                "Error: wb_motor_set_velocity() called with an invalid 'velocity' argument (NaN).",
                file=sys.stderr,
            )
            return
        if not _is_real(velocity):
            raise TypeError(f"velocity must be a number of rad/s, not {velocity!r}")
        most = self.getMaxVelocity()
        if abs(velocity) > most + 1e-9:
            if self._strict:
                raise OutOfRangeError(
                    f"velocity {velocity} rad/s is outside +-{most:.2f} rad/s: "
                    "refused, not clamped"
                )
            print(
                f'WARNING: e-puck > RotationalMotor "{self._name}": The requested velocity '
                f"{velocity:g} exceeds 'maxVelocity' = {most:g}.",
                file=sys.stderr,
            )
            velocity = math.copysign(most, velocity)
        self._velocity = self._drivable(float(velocity))
        self._apply()

    def _drivable(self, velocity: float) -> float:
        """``velocity`` within what the firmware drives, where the model allows more (the
        e-puck2: maxVelocity 7.536 rad/s, the firmware clamps at 1100 steps/s): clamped
        with one warning a motor, refused under ``--strict`` (docs/webots-compat.md)."""
        drivable = self._drivable_rad_s()
        if abs(velocity) <= drivable + 1e-9:
            return velocity
        profile = self._core.channel.profile
        why = (
            f"the {profile.firmware} firmware drives a wheel at {profile.max_speed_steps} "
            f"steps/s ({drivable:.4g} rad/s) at most, below the model's maxVelocity "
            f"{self.getMaxVelocity():.4g}"
        )
        if self._strict:
            raise OutOfRangeError(f"velocity {velocity:g} rad/s of {self._name!r}: {why}")
        if not self._told_clamp:
            self._told_clamp = True
            log.warning("%s: velocity %g rad/s clamped to %.4g: %s (said once)",
                        self._name, velocity, drivable, why)  # fmt: skip
        return math.copysign(drivable, velocity)

    def setPosition(self, position: float) -> None:
        """``inf`` for velocity control; a finite angle (rad) to drive the wheel there."""
        if not _is_real(position):
            raise TypeError(f"position must be a number of rad or inf, not {position!r}")
        self._target = float(position)
        if not math.isinf(self._target) and not self._core.encoders.enabled:
            self._core.encoders.enable(int(self._position_period_ms()))
        self._apply()

    def _apply(self, stepping: bool = False) -> None:
        speeds = list(self._core.motors.speed)
        if math.isinf(self._target):
            # Webots' velocity control: the velocity's own sign gives the direction, whichever
            # infinity the position is (WbMotor ignores the target once it is infinite).
            speeds[self._side] = round(rad_s_to_steps(self._ramped(self._velocity, stepping)))
        else:
            speeds[self._side] = self._position_speed()
        self._core.motors.set_speed(speeds[0], speeds[1])

    def _ramped(self, wanted_rad_s: float, stepping: bool) -> float:
        """``wanted_rad_s``, or with an acceleration set, one step's worth closer to it
        at each step (the speed sent stays as it is between steps)."""
        if self._acceleration > 0:
            if not stepping:
                return self._sent_rad_s
            most = self._acceleration * self._position_period_ms() / 1000.0
            change = max(-most, min(most, wanted_rad_s - self._sent_rad_s))
            wanted_rad_s = self._sent_rad_s + change
        self._sent_rad_s = wanted_rad_s
        return wanted_rad_s

    def _position_speed(self) -> int:
        """Steps/s towards the target (:func:`ego.devices.position_control.position_speed`)."""
        if not self._core.encoders.has_values:
            return 0
        current = self._core.encoders.radians[self._side]
        return position_speed(self._target, current, self._velocity)

    def _position_period_ms(self) -> float:
        if self._period_ms is not None:
            return self._period_ms
        from ego.faces.default_robot import current_context

        return current_context().options.basic_time_step_ms

    def step_update(self) -> None:
        """Position control, or an acceleration ramp: recompute the speed after each step."""
        if not math.isinf(self._target) or (
            self._acceleration > 0 and self._sent_rad_s != self._velocity
        ):
            self._apply(stepping=True)


class LED(Device):
    """An LED: ``set(0)`` off, any other value on (Webots' meaning for the e-puck's LEDs);
    an RGB LED (where the firmware has them: the e-puck2's led1, led3, led5, led7) takes
    its colour, ``set(0xRRGGBB)``, as Webots' RGB LEDs do."""

    def set(self, value: int) -> None:
        """Any number, as Webots takes it (``True`` and ``1.0`` switch it on); strict: ints."""
        if self._strict and (isinstance(value, bool) or not isinstance(value, numbers.Integral)):
            raise TypeError(f"LED value must be an int, not {type(value).__name__}")
        if not isinstance(value, numbers.Real):
            raise TypeError(f"LED value must be a number, not {type(value).__name__}")
        leds = self._core.leds
        if leds.index(self._name) in leds.rgb:
            leds.set(self._name, int(value))
        else:
            leds.set(self._name, 1 if int(value) else 0)

    def get(self) -> int:
        return self._core.leds.get(self._name)

    value = property(lambda self: self.get(), lambda self, v: self.set(v))


class Camera(Sensor):
    """The camera, BGRA images as Webots gives them. The Webots faces give it Webots'
    e-puck size (52x39) unless ``ego run --camera WxH`` asks another
    (:func:`webots_camera_size`); the E-GO face keeps 640x480."""

    def enable(self, samplingPeriod: int) -> None:
        self._core.camera.enable(samplingPeriod)

    def disable(self) -> None:
        self._core.camera.disable()

    def getSamplingPeriod(self) -> int:
        return self._core.camera.sampling_period or 0

    def getWidth(self) -> int:
        return int(self._core.camera.width)

    def getHeight(self) -> int:
        return int(self._core.camera.height)

    def getFov(self) -> float:
        return float(self._core.camera.fov_rad)

    def setFov(self, fov: float) -> None:
        """Webots zooms within getMinFov()..getMaxFov(); the e-puck's optics are fixed, so
        only the emulator's renderer follows (a real camera keeps its own)."""
        self._core.camera.fov_rad = fov

    def getMinFov(self) -> float:
        return float(self._core.camera.fov_rad)

    def getMaxFov(self) -> float:
        return float(self._core.camera.fov_rad)

    def getNear(self) -> float:
        """The PROTO's near plane, metres."""
        return CAMERA_NEAR_M

    def getFocalLength(self) -> float:
        return 0.0  # no Focus node on the e-puck's camera, as Webots answers

    def getFocalDistance(self) -> float:
        return 0.0

    def getExposure(self) -> float:
        """The V4L2 brightness control stands for Webots' exposure (None set: 1.0)."""
        brightness = self._core.camera.brightness
        return 1.0 if brightness is None else brightness / 64.0

    def setExposure(self, exposure: float) -> None:
        self._core.camera.brightness = max(0, min(255, round(float(exposure) * 64)))

    def hasRecognition(self) -> bool:
        return False

    def getRecognitionNumberOfObjects(self) -> int:
        return 0

    def getRecognitionObjects(self) -> list[object]:
        return []

    def getRecognitionSamplingPeriod(self) -> int:
        return 0

    def recognitionEnable(self, samplingPeriod: int) -> None:
        """Webots says the camera has no Recognition node; so does this."""
        print(
            "Error: wb_camera_recognition_enable() called on a Camera without Recognition node.",
            file=sys.stderr,
        )

    def getMinFocalDistance(self) -> float:
        return 0.0

    def getMaxFocalDistance(self) -> float:
        return 0.0

    def setFocalDistance(self, focal_distance: float) -> None:
        """The e-puck's camera has no Focus node: nothing to set, as Webots ignores it."""

    width = property(lambda self: self.getWidth())
    height = property(lambda self: self.getHeight())
    fov = property(lambda self: self.getFov(), lambda self, f: self.setFov(f))
    min_fov = property(lambda self: self.getMinFov())
    max_fov = property(lambda self: self.getMaxFov())
    near = property(lambda self: self.getNear())
    image = property(lambda self: self.getImage())
    exposure = property(lambda self: self.getExposure(), lambda self, e: self.setExposure(e))
    focal_length = property(lambda self: self.getFocalLength())
    focal_distance = property(
        lambda self: self.getFocalDistance(), lambda self, d: self.setFocalDistance(d)
    )
    min_focal_distance = property(lambda self: self.getMinFocalDistance())
    max_focal_distance = property(lambda self: self.getMaxFocalDistance())

    def getImage(self) -> bytes:
        """BGRA bytes, row by row, as Webots' ``getImage``."""
        return bytes(self._core.camera.image_bgra())

    def getImageArray(self) -> npt.NDArray[np.int64]:
        """``image[x][y] = [r, g, b]`` as Webots' ``getImageArray``.

        A NumPy array of int64 rather than nested lists: it indexes, iterates,
        compares and sums as the lists do (no uint8 wrap-around), 40 times faster at
        640x480; ``.tolist()`` gives Webots' lists.
        """
        return self._core.camera.image.transpose(1, 0, 2).astype(np.int64)

    def saveImage(self, filename: str, quality: int) -> int:
        """PNG or JPEG by extension; 0 on success, -1 on failure (Webots' convention).

        As Webots prints why, the reason of a failure is logged as a warning.
        """
        try:
            self._core.camera.save_image(filename, quality)
        except (EgoError, OSError, ValueError) as exc:
            log.warning("saveImage(%r) failed: %s", filename, exc)
            return -1
        return 0

    @staticmethod
    def imageGetRed(image: bytes, width: int, x: int, y: int) -> int:
        return image[4 * (y * width + x) + 2]

    @staticmethod
    def imageGetGreen(image: bytes, width: int, x: int, y: int) -> int:
        return image[4 * (y * width + x) + 1]

    @staticmethod
    def imageGetBlue(image: bytes, width: int, x: int, y: int) -> int:
        return image[4 * (y * width + x)]

    @staticmethod
    def imageGetGray(image: bytes, width: int, x: int, y: int) -> int:
        i = 4 * (y * width + x)
        return (image[i] + image[i + 1] + image[i + 2]) // 3

    imageGetGrey = imageGetGray


class Gyro(Sensor):
    """Webots' Gyro: x, y, z through the model's lookup table (NaN while not enabled)."""

    def getValues(self) -> list[float]:
        family = self._core.device(self._name)
        readings = family.readings() if self._readable() else None
        if readings is None:
            return [_NAN, _NAN, _NAN]
        return [float(v) for v in readings]

    def getLookupTable(self) -> list[float]:
        return list(webots_model(self._core.device(self._name)).lookup or ())

    value = property(lambda self: self.getValues())
    lookup_table = property(lambda self: self.getLookupTable())


class Speaker(Device):
    """Webots' Speaker on the robot's own sounds: ``playSound`` plays the firmware's sound
    a file is named after (``mario.wav``, ``star_wars``, ``tone_4khz``...: the family's
    :class:`~ego.devices.sound.Melody`); any other sound, and ``speak``, are refused
    under ``--strict`` and told on stderr otherwise, as Webots tells a missing file."""

    @staticmethod
    def playSound(
        left: Speaker, right: Speaker, sound: str, volume: float = 1.0, pitch: float = 1.0,
        balance: float = 0.0, loop: bool = False,
    ) -> None:  # fmt: skip
        speaker = left if isinstance(left, Speaker) else right
        family = speaker._core.sound
        melody = family.melody_named(sound)
        if melody is None:
            speaker._refuse(f"cannot play {sound!r}: the robot plays {family.sound_names()}")
            return
        family.play(melody)

    def stop(self, sound: str | None = None) -> None:
        self._core.sound.stop()

    def isSoundPlaying(self, sound: str | None = None) -> bool:
        """Whether ego asked a sound last (the firmware does not say when one ends)."""
        last = self._core.sound.last
        return last is not None and (sound is None or self._core.sound.melody_named(sound) == last)

    def speak(self, text: str, volume: float = 1.0) -> None:
        self._refuse("the robot has no speech synthesis")

    def isSpeaking(self) -> bool:
        return False

    def _refuse(self, why: str) -> None:
        if self._strict:
            raise UnsupportedDeviceError(f"speaker {self._name!r}: {why}")
        print(f"Error: speaker {self._name!r}: {why}.", file=sys.stderr)


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
