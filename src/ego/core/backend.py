"""What every backend shares: the :class:`Opened` bundle, the :class:`Backend` protocol, and
the options a backend declares (:class:`BackendOptions`).

Concrete backends import this module, never the registry (:mod:`ego.backends`), which
loads them by name only when a port of their scheme is opened.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, ClassVar, Protocol, TypeVar

from ego.seam.profile import Firmware

if TYPE_CHECKING:
    from ego.camera import FrameSource
    from ego.core.environment import Environment
    from ego.core.ground_truth import GroundTruth
    from ego.core.scene import Scene
    from ego.core.scheduler import Pacer
    from ego.i2c.bus import I2CAccess
    from ego.seam.channel import Channel

__all__ = ["Backend", "BackendOptions", "Opened", "check"]

_Options = TypeVar("_Options", bound="BackendOptions")


@dataclass
class Opened:
    """What a backend opened for a Robot."""

    channel: Channel
    #: Makes the robot's camera source when it is first used; None: this robot has none.
    camera: Callable[[], FrameSource] | None = None
    #: The simulator behind a simulated robot (its world is the ground truth), else None.
    ground_truth: GroundTruth | None = None
    #: Releases what the backend started beside the channel (an emulator thread).
    closers: list[Callable[[], None]] = field(default_factory=list)
    #: Whether the robot is driven over a network (Webots' MODE_REMOTE_CONTROL).
    remote: bool = False
    #: The robot's own I2C bus (the Overo's), opened at first need; None: out of reach.
    i2c: I2CAccess | None = None
    #: The simulated world's solids, for a Webots Supervisor (None: a real robot).
    scene: Scene | None = None
    #: What paces the steps instead of the wall clock (an emulator's virtual time).
    pacer: Pacer | None = None
    #: When the last reply came, in seconds, for the checks of a reply's plausibility (a
    #: replay: when the recorded robot's came); None: the host's monotonic clock.
    reply_clock: Callable[[], float] | None = None

    def close(self) -> None:
        """Close the channel and everything beside it; idempotent."""
        self.channel.close()
        while self.closers:
            self.closers.pop()()


def check(checker: Callable[[Any], object]) -> dict[str, object]:
    """Field metadata naming the function that checks an option's value and returns the
    value to bind (raising its own error, as ``check_baudrate`` does), instead of the
    generic type check: ``baudrate: int | None = field(default=None,
    metadata=check(check_baudrate))``."""
    return {"check": checker}


@dataclass(frozen=True, kw_only=True)
class BackendOptions:
    """The options of a backend: a frozen dataclass, one field per option, each with its
    default. Every backend takes ``firmware``; a backend adds its own in a subclass.

    A value of None stands for the backend's default, for every option: passing
    ``seed=None`` is passing no seed. :func:`ego.backends.bind_options` builds one from
    the options a caller gave, and refuses a name the class does not have or a value
    that is not of its field's type.
    """

    #: The firmware profile to use, or its name (None or "auto": detect it).
    firmware: Firmware | None = field(default=None, metadata=check(Firmware.choose))

    def with_environment(self: _Options, environment: Environment) -> _Options:
        """These options with the environment's defaults filled in where none was given
        (a served robot's secret from EGO_SECRET_FILE); by default, these options."""
        return self

    @classmethod
    def narrow(cls: type[_Options], options: BackendOptions) -> _Options:
        """``options`` as this class (what the registry bound for this backend)."""
        if not isinstance(options, cls):
            raise TypeError(f"{cls.__name__} expected, not {type(options).__name__}")
        return options


class Backend(Protocol):
    """Opens the channel to one kind of robot with the options it declares.

    ``options`` is the backend's :class:`BackendOptions` subclass: the registry binds and
    checks a port's options against it before :meth:`open` is called, so a misspelt
    option, or one of the wrong type, never reaches the backend.
    """

    options: ClassVar[type[BackendOptions]]

    def open(self, port: str, options: BackendOptions) -> Opened:
        """Open ``port`` with ``options`` (an instance of :attr:`options`)."""
        ...
