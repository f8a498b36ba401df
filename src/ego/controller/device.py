"""Webots' ``Device``: a named device of the robot, made by the Robot or by name."""

from __future__ import annotations

import math
import numbers
from collections.abc import Callable
from typing import TYPE_CHECKING, TypeVar

from ego.controller.node_types import node_type
from ego.devices.table import find
from ego.errors import EgoError, UnknownDeviceError

if TYPE_CHECKING:
    from ego.core.robot import Robot as CoreRobot

DeviceT = TypeVar("DeviceT", bound="Device")

__all__ = ["Device", "view", "view_class"]

NAN = float("nan")

#: The Webots class of each kind of :mod:`ego.devices.table` the e-puck has (``Motor``...):
#: each class's module registers it (:func:`view`), so nothing here imports them.
_VIEWS: dict[str, type[Device]] = {}


def view(kind: str) -> Callable[[type[DeviceT]], type[DeviceT]]:
    """Register the decorated class as the Webots view of the table's ``kind``."""

    def register(cls: type[DeviceT]) -> type[DeviceT]:
        _VIEWS[kind] = cls
        return cls

    return register


def view_class(name: str) -> type[Device] | None:
    """The Webots class of a device name; None for ego's names Webots has no device for
    (the microphones)."""
    found = find(name)
    if found is None or not found.webots_device:
        return None
    return _VIEWS.get(found.kind)


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
            self._made_by_name(core)
            return
        if strict is None:
            from ego.faces.default_robot import current_context

            strict = current_context().options.strict
        self._core = core
        self._name = name
        self._strict = strict

    def _made_by_name(self, name: str) -> None:
        """Share the state of the robot's device ``name``. ``Motor("left wheel motor")``
        has it already (``__new__``); a subclass whose own ``__init__`` takes no name
        and calls ``super().__init__("camera")``, as course controllers write it, gets
        it here, checked as ``__new__`` checks it."""
        if "_core" not in self.__dict__:
            self.__dict__ = _by_name(type(self), name).__dict__

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
