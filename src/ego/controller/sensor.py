"""Webots' ``Sensor``, the base of every sensor class (and the one-value sensors' base)."""

from __future__ import annotations

from typing import TYPE_CHECKING

from ego.controller.device import Device
from ego.devices.base import ArraySensor, Sampled
from ego.errors import UnsupportedDeviceError
from ego.faces.webots_model import webots_model

if TYPE_CHECKING:
    from ego.core.ground_truth import GroundTruth
    from ego.core.robot import Robot as CoreRobot

__all__ = ["GroundTruthDevice", "Sensor"]


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
            self._made_by_name(core)
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


class GroundTruthDevice(Device):
    """A device the real e-puck lacks, read from the emulator's world where it declares it
    (localisation labs add a GPS or a compass to the e-puck in Webots)."""

    def __init__(
        self, core: CoreRobot | str, name: str = "", *, strict: bool | None = None
    ) -> None:
        if isinstance(core, str):
            self._made_by_name(core)  # the robot's own, already set up
            return
        super().__init__(core, name, strict=strict)
        self._period = 0

    def _truth(self) -> GroundTruth:
        truth = self._core.ground_truth
        if truth is None:  # made only where the world declares it: a simulated robot
            raise UnsupportedDeviceError(f"{self._name!r}: a real robot has no ground truth")
        return truth

    def _values(self) -> tuple[float, float, float] | None:
        """What the world's device of this name reads (ground_truth.TrueWorld's
        device_values), None while disabled."""
        world = self._truth().true_world if self._period else None
        return None if world is None else world.device_values(self._name)

    def enable(self, samplingPeriod: int) -> None:
        self._period = int(samplingPeriod)

    def disable(self) -> None:
        self._period = 0

    def getSamplingPeriod(self) -> int:
        return self._period
