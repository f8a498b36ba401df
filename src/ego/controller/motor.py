"""Webots' ``Motor``: a wheel, by velocity or by position."""

from __future__ import annotations

import logging
import math
import sys
from typing import TYPE_CHECKING

from ego.controller.device import Device, _is_real, _sibling, view
from ego.devices.motors import rad_s_to_steps, steps_to_rad_s
from ego.devices.position_control import position_speed
from ego.devices.table import spec
from ego.errors import OutOfRangeError

if TYPE_CHECKING:
    from ego.core.robot import Robot as CoreRobot

__all__ = ["Motor"]

log = logging.getLogger(__name__)


@view("Motor")
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
            self._made_by_name(core)  # the robot's own motor, already set up
            return
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
    target_velocity = property(lambda self: self.getVelocity(), lambda self, v: self.setVelocity(v))
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
                    f"velocity {velocity} rad/s is outside +-{most:.2f} rad/s: refused, not clamped"
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

    def reset(self) -> None:
        """As Webots' ``WbMotor::reset`` leaves a motor at ``simulationReset``: the wheel
        held where it is (position control towards the joint's position, 0 rad once the
        counters are back at 0), the velocity back at maxVelocity, no acceleration ramp,
        nothing sent yet. The caller stops the wheels and zeroes the counters."""
        self._target = 0.0
        self._velocity = self._drivable_rad_s()
        self._acceleration = -1.0
        self._sent_rad_s = 0.0

    def step_update(self) -> None:
        """Position control, or an acceleration ramp: recompute the speed after each step."""
        if not math.isinf(self._target) or (
            self._acceleration > 0 and self._sent_rad_s != self._velocity
        ):
            self._apply(stepping=True)
