"""What every device family shares: names, sampling periods, due checks, firmware checks,
and the transaction each takes part in once a step.

A device family is one wire command serving several named devices (``N`` serves
``ps0``..``ps7``). As in the thesis, a sensor's command is queued only when one of its
members' sampling period is due, an actuator's only when its value changed; the robot
gathers everything due in one step into one batch.

Each step is a transaction over every family's parts (a part is a sensor or an actuator,
never both; a family like the motors has one of each):

1. ``plan(now_ms)``: the requests this part wants in the batch now;
2. the batch is exchanged, and each reply checked by the part that asked:
   ``validate(request, values, now_s)`` returns a :class:`Verdict` and changes nothing;
3. if any verdict is a problem, each part hears it (``refused``: remember a suspect
   reading, queue a correction) and the batch is planned again;
4. else ``apply(request, values, now_ms)``: the only change after a good reply;
5. after a dsPIC restart, ``reset()``: re-send what the dsPIC lost.

The batch order is declared by each command's :data:`PHASE` (setters first), never
inferred.
"""

from __future__ import annotations

import abc
import enum
import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar, Protocol, runtime_checkable

from ego.devices.table import TABLE, DeviceTable
from ego.errors import DeviceError, UnknownDeviceError, UnsupportedDeviceError
from ego.i2c.side import NO_I2C, OveroI2C
from ego.seam.batch import Request
from ego.seam.profile import Command, Profile
from ego.seam.validate import MAX_PERIOD_MS, check_int

if TYPE_CHECKING:
    from ego.i2c.chips import Chip

__all__ = [
    "FINE",
    "PHASE",
    "ActingFamily",
    "Actuator",
    "ArraySensor",
    "Device",
    "Phase",
    "Sampled",
    "Sensor",
    "Verdict",
    "check_int",
    "out_of_range",
]



def out_of_range(what: str, values: Sequence[float], low: float, high: float) -> str | None:
    """A reason if any of ``values`` lies outside low..high, else None."""
    bad = [v for v in values if not low <= v <= high]
    return f"{what} value {bad[0]} outside {low}..{high}" if bad else None


class Phase(enum.IntEnum):
    """Where a command goes in a batch: every setter before every read, so that the ``E``
    confirming the speeds follows every command of the batch (a byte of any of them
    misread as ``D`` is caught too: ``L`` and ``D`` differ by one bit) and ``P`` precedes
    the ``Q`` that must see it."""

    SET = 0
    READ = 1


#: Each command's phase (docs/protocol.md): the three that change the dsPIC's state.
PHASE: dict[Command, Phase] = {
    command: Phase.SET
    if command in (Command.SET_SPEED, Command.SET_LED, Command.SET_STEPS)
    else Phase.READ
    for command in Command
}


@dataclass(frozen=True, slots=True)
class Verdict:
    """What a part makes of one reply: fine, or a problem (ask the batch again), with
    what the part should remember (``note``) and send again (``correction``)."""

    problem: str | None = None
    correction: Request | None = None
    note: object = None

    @property
    def fine(self) -> bool:
        return self.problem is None


#: The verdict of a reply nothing is wrong with.
FINE = Verdict()


class Device:
    """A family of named devices behind one firmware, and a part of the step transaction.

    A family with a sensor and an actuator side (the motors, the encoders) lists them in
    :attr:`parts`; every other family is its own only part.
    """

    #: The family the device table calls this one (its rows' ``family``, the Robot
    #: attribute: "proximity"), set by its declaration (``@TABLE.declare``); its
    #: :attr:`names` are the table's, never written here.
    table_family: ClassVar[str] = ""
    #: The Webots names of the devices in this family (``ps0``..``ps7``), from the table.
    names: ClassVar[tuple[str, ...]] = ()
    #: Short family name for messages.
    family: ClassVar[str] = "device"
    #: Whether Webots knows its members as devices (``getDevice``); the battery is not
    #: one (Webots reads it through the robot: ``batterySensorGetValue``).
    webots_device: ClassVar[bool] = True
    def __init__(self, profile: Profile) -> None:
        self._profile = profile

    @property
    def profile(self) -> Profile:
        return self._profile

    def readings(self) -> list[float] | None:
        """What a telemetry sample shows of this family (its ``Series``' lines), or None
        while it has nothing to show (disabled, not sampled yet, or not served)."""
        return None

    def set_profile(self, profile: Profile) -> None:
        """The firmware changed (re-detected after a restart)."""
        self._profile = profile

    @property
    def member_names(self) -> tuple[str, ...]:
        """The names that exist under the connected firmware."""
        return self.names

    def served_names(self, table: DeviceTable = TABLE) -> tuple[str, ...]:
        """The family's names whose table row the connected firmware serves (a family
        the device table gives to some firmwares only: the e-puck2's ``tof``...)."""
        firmware = self._profile.firmware
        return tuple(n for n in self.names if table.spec(n).served_by(firmware))

    def check_name(self, name: str) -> str:
        if name not in self.member_names:
            raise UnknownDeviceError(
                f"{name!r} is not a {self.family} device; valid names: "
                f"{', '.join(self.member_names)}"
            )
        return name

    def require(self, command: Command) -> None:
        """Refuse at once a device this firmware cannot serve (it never reads zeros)."""
        if not self._profile.supports(command):
            raise UnsupportedDeviceError(
                f"the {self._profile.firmware} firmware ({self._profile.description}) cannot "
                f"serve the {self.family} (wire command {command.letter!r})"
            )

    @property
    def parts(self) -> tuple[Device, ...]:
        """The transaction's participants this family is made of."""
        return (self,)

    def plan(self, now_ms: int) -> list[Request]:
        """The commands this part wants in the batch of the step starting at ``now_ms``."""
        return []

    def validate(self, request: Request, values: Sequence[float], now_s: float) -> Verdict:
        """What these reply values say, without changing anything: the plausibility guard.

        The link has no checksum, so a flipped bit inside a reply of the right length
        reaches here unseen. Values outside their physical range, or a step counter that
        moved further than the wheels can turn, are caught; a flip that stays in range is
        not (``now_s`` is when the reply came, on the host's monotonic clock).
        """
        return FINE

    def refused(self, verdict: Verdict, now_s: float) -> None:
        """A reply of this part's was refused with ``verdict``: the batch goes again."""

    def apply(self, request: Request, values: Sequence[float], now_ms: int, now_s: float) -> None:
        """The batch went through: take this request's reply values (none for a setter)."""

    def reset(self) -> None:
        """The dsPIC restarted or the port was re-plugged: re-send what it lost."""

    def __repr__(self) -> str:
        return f"<{type(self).__name__} {', '.join(self.member_names)}>"


@runtime_checkable
class Sampled(Protocol):
    """A family whose members are read at a sampling period: a sensor, or the read side
    of a family that also acts (the motors' speeds held, the encoders' counters)."""

    def enable(self, period_ms: int, names: Iterable[str] | None = None) -> None: ...

    def disable(self, names: Iterable[str] | None = None) -> None: ...

    def sampling_period(self, name: str | None = None) -> int | None: ...

    @property
    def has_values(self) -> bool: ...


class Sensor(Device, abc.ABC):
    """A sensor family: members enabled with a sampling period, fetched when due.

    The family's command goes out when any enabled member's period has elapsed since
    the last fetch; one fetch refreshes every member. Where the firmware leaves the
    family's devices on the Overo's own I2C bus (``Profile.i2c``) and their chip answers
    there, the family is read over that bus instead (ego.i2c), with the same values.
    """

    command: ClassVar[Command]

    def __init__(self, profile: Profile) -> None:
        super().__init__(profile)
        self._periods: dict[str, int] = {}
        self._last_fetch_ms: int | None = None
        self._sampled_ms: int | None = None
        self._i2c: OveroI2C | None = None
        self._via: Chip | None = None

    def bind_i2c(self, side: OveroI2C) -> None:
        """The robot's I2C bus, for the devices the firmware leaves on it."""
        self._i2c = side

    @property
    def i2c_chip(self) -> Chip | None:
        """The chip this family is read from over I2C; None: over the line."""
        return self._via if self._periods else None

    def enable(self, period_ms: int, names: Iterable[str] | None = None) -> None:
        """Sample the named members (all by default) every ``period_ms`` milliseconds."""
        period = check_int("sampling period", period_ms, 1, MAX_PERIOD_MS, " ms")
        members = self.member_names if names is None else [self.check_name(n) for n in names]
        self._route(self.command_for_enable())
        for name in members:
            self._periods[name] = period

    def _route(self, command: Command) -> None:
        """The way to the devices: the I2C chip the profile names if it answers, else the
        line; UnsupportedDeviceError naming the way out when neither serves them."""
        chip_name = self._profile.i2c.get(command)
        via = None
        if chip_name is not None:
            side = self._side()
            via = side.find(chip_name)
            if via is None and not self._profile.supports(command):
                raise UnsupportedDeviceError(side.absent(chip_name))
        if via is None:
            self.require(command)
        self._via = via  # only once the way is sure: a refused enable changes nothing

    def _side(self) -> OveroI2C:
        return NO_I2C if self._i2c is None else self._i2c

    def i2c_hint(self) -> str:
        """Why the I2C bus did not serve this family, where the profile has it there."""
        chip_name = self._profile.i2c.get(self.command_for_enable())
        return "" if chip_name is None else f"; {self._side().absent(chip_name)}"

    def command_for_enable(self) -> Command:
        return self.command

    def disable(self, names: Iterable[str] | None = None) -> None:
        """Stop sampling the named members (all by default)."""
        members = self.member_names if names is None else [self.check_name(n) for n in names]
        for name in members:
            self._periods.pop(name, None)
        if not self._periods:
            self._last_fetch_ms = None

    def sampling_period(self, name: str | None = None) -> int | None:
        """The member's (or the family's shortest) period in ms; None when disabled."""
        if name is not None:
            return self._periods.get(self.check_name(name))
        return min(self._periods.values()) if self._periods else None

    @property
    def enabled(self) -> bool:
        return bool(self._periods)

    def is_due(self, now_ms: int) -> bool:
        period = self.sampling_period()
        if period is None:
            return False
        return self._last_fetch_ms is None or now_ms - self._last_fetch_ms >= period

    def plan(self, now_ms: int) -> list[Request]:
        if self.i2c_chip is not None:
            return []  # read over I2C, beside the batch (ego.devices.i2c_step.run_i2c_step)
        return [Request(self.current_command())] if self.is_due(now_ms) else []

    def current_command(self) -> Command:
        return self.command

    def apply(self, request: Request, values: Sequence[float], now_ms: int, now_s: float) -> None:
        self._last_fetch_ms = now_ms
        self._sampled_ms = now_ms
        self.take(values)

    @abc.abstractmethod
    def take(self, values: Sequence[float]) -> None:
        """Store one reply's values."""

    @property
    def has_values(self) -> bool:
        return self._sampled_ms is not None

    def require_values(self) -> None:
        """Reading before the first sample is an error, never a silent zero."""
        if not self.has_values:
            state = "not enabled" if not self.enabled else "not sampled yet"
            raise DeviceError(f"{self.family} {state}: enable them and call step() before reading")

    def set_profile(self, profile: Profile) -> None:
        super().set_profile(profile)
        command = self.command_for_enable()
        if self._via is not None and profile.i2c.get(command) != self._via.name:
            self._via = None
        if self._periods and self._via is None and not profile.supports(command):
            self._periods.clear()
            raise UnsupportedDeviceError(
                f"after a restart the firmware is {profile.firmware}, which cannot serve the "
                f"{self.family}"
            )

    def reset(self) -> None:
        self._last_fetch_ms = None  # fetch again at the next step

    def missing(self, why: str) -> UnsupportedDeviceError:
        """Disable the family and return the error saying the robot cannot serve it.

        For a reply that proves the device absent (a firmware answering zeros or 0xFFFF
        for hardware the robot lacks): the value is never delivered as a reading.
        """
        self._periods.clear()
        self._last_fetch_ms = self._sampled_ms = None
        return UnsupportedDeviceError(f"no {self.family} data on this robot: {why}")


class Actuator(Device):
    """An actuator family: a command goes out once, when its value changed."""

    def __init__(self, profile: Profile) -> None:
        super().__init__(profile)
        self._pending: dict[object, Request] = {}

    def queue(self, key: object, request: Request) -> None:
        self._pending[key] = request

    def plan(self, now_ms: int) -> list[Request]:
        return list(self._pending.values())

    def apply(self, request: Request, values: Sequence[float], now_ms: int, now_s: float) -> None:
        # Done, unless a newer value for the same key was queued meanwhile.
        for key, pending in list(self._pending.items()):
            if pending == request:
                del self._pending[key]


class ArraySensor(Sensor):
    """A sensor family whose reply is one integer per member, in member order."""

    #: What the 12-bit ADC can give; a value outside it came from a corrupted byte.
    value_range: ClassVar[tuple[int, int]] = (0, 4095)

    def __init__(self, profile: Profile) -> None:
        super().__init__(profile)
        self._values: tuple[int, ...] = ()
        self._index: dict[str, int] = {}

    def validate(self, request: Request, values: Sequence[float], now_s: float) -> Verdict:
        return Verdict(out_of_range(self.family, values, *self.value_range))

    def take(self, values: Sequence[float]) -> None:
        names = self.member_names
        self._values = tuple(int(v) for v in values[: len(names)])
        if len(self._index) != len(names):
            self._index = {name: i for i, name in enumerate(names)}

    def reading(self, name: str) -> float:
        """One member's last sample, NaN while it is not enabled or not sampled yet
        (Webots' convention): the faces' per-step read, kept to a few dictionary looks."""
        if self._sampled_ms is None or name not in self._periods:
            return math.nan
        return float(self._values[self._index[name]])

    @property
    def values(self) -> tuple[int, ...]:
        """Every member's last sample, in name order."""
        self.require_values()
        return self._values

    def readings(self) -> list[float] | None:
        return [float(v) for v in self._values] if self.has_values else None

    def value(self, name: str) -> int:
        """One member's last sample."""
        self.require_values()
        return self._values[self.member_names.index(self.check_name(name))]


class ActingFamily(Device):
    """A family with an actuator part and a sensor part behind one public object (the
    motors: speeds set and held; the encoders: counters set and read). Sampling is the
    sensor part's; the transaction sees both parts."""

    def __init__(self, profile: Profile, acting: Device, reading: Sensor) -> None:
        super().__init__(profile)
        self._acting = acting
        self._reading = reading

    @property
    def parts(self) -> tuple[Device, ...]:
        return (self._acting, self._reading)

    def set_profile(self, profile: Profile) -> None:
        super().set_profile(profile)
        for part in self.parts:
            part.set_profile(profile)

    def enable(self, period_ms: int, names: Iterable[str] | None = None) -> None:
        """Read the family's values every ``period_ms`` milliseconds."""
        self._reading.enable(period_ms, names)

    def disable(self, names: Iterable[str] | None = None) -> None:
        self._reading.disable(names)

    def sampling_period(self, name: str | None = None) -> int | None:
        return self._reading.sampling_period(name)

    @property
    def enabled(self) -> bool:
        return self._reading.enabled

    @property
    def has_values(self) -> bool:
        return self._reading.has_values
