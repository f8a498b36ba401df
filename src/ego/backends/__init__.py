"""Backends by URL scheme: where a Robot's channel, camera and ground truth come from.

As pyserial picks a port class by URL and python-can an interface by name, ``Robot(port)``
picks a backend by the port's scheme, and only here:

============  ==========================================================================
scheme        backend
============  ==========================================================================
(none)        a serial port or any pyserial URL (``/dev/ttyS0``, ``/dev/rfcomm0``,
              ``socket://``, ``loop://``, ``spy://``): :class:`SerialBackend`
``tcp``       a robot served by ``ego serve``, over TCP: :class:`RemoteBackend`
``udp``       the same over UDP
``sim``       the dsPIC emulator, found through the ``ego.backends`` entry point that
              the ``firmware_sim`` package declares (ego itself never imports it)
``zenoh``     a robot served as a Zenoh node (``zenoh://NAME``, ``ego serve --zenoh``):
              :mod:`ego.backends.zenoh_remote`
``replay``    a run recorded with ``ego run --record`` (``replay://run.mcap``), answering
              a controller as the robot did: :mod:`ego.backends.replay`
============  ==========================================================================

Each backend opens a :class:`~ego.core.channel.Channel` (the seam under ``Robot``) and takes
the options it knows: a serial port its baud rate and link settings, the emulator its
seed, the network its secret. Beside the channel it may hand in the robot's own I2C bus
(:class:`~ego.i2c.bus.I2CAccess`, opened at first need), where the stock firmware leaves
the ground module and a rev 1.3's accelerometer to the Overo: the Overo's
``/dev/i2c-3`` on its own UART, the emulator's model of the bus for ``sim``. A new
backend (Bluetooth discovery, a distributed engine, another robot) is one module with a
class that has :meth:`Backend.open`, registered under the ``ego.backends`` entry point
group or with :func:`register`; nothing in ``Robot`` changes.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Protocol

from ego.errors import PortNotFoundError
from ego.serial.protocol import Firmware

if TYPE_CHECKING:
    from ego.camera import FrameSource
    from ego.core.channel import Channel
    from ego.core.ground_truth import GroundTruth
    from ego.core.scene import Scene
    from ego.core.scheduler import Pacer
    from ego.i2c.bus import I2CAccess

__all__ = [
    "ENTRY_POINT_GROUP",
    "Backend",
    "Opened",
    "find_backend",
    "open_port",
    "register",
    "scheme_of",
    "takes_option",
]

#: Where packages declare backends: ``[project.entry-points."ego.backends"] sim = ...``.
ENTRY_POINT_GROUP = "ego.backends"


@dataclass
class Opened:
    """What a backend opened for a Robot."""

    channel: Channel
    #: Makes the robot's camera source when it is first used; None: this robot has none.
    camera: Callable[[], FrameSource] | None = None
    #: What the simulator behind a simulated robot knows of it, else None.
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


class Backend(Protocol):
    """Opens the channel to one kind of robot; each backend takes the options it knows.

    ``firmware`` forces a firmware profile (None: detect it); a backend raises TypeError
    for an option it does not know, so a misspelt one never passes unnoticed.
    """

    @property
    def open(self) -> Callable[..., Opened]:
        """``open(port, *, firmware, **options) -> Opened``, each with its own options."""
        ...


_REGISTRY: dict[str, Callable[[], Backend]] = {
    "serial": lambda: _serial_backend(),
    "tcp": lambda: _remote_backend(),
    "udp": lambda: _remote_backend(),
    "unix": lambda: _remote_backend(),
    "replay": lambda: _replay_backend(),
    "zenoh": lambda: _zenoh_backend(),
}


def _serial_backend() -> Backend:
    from ego.backends.serial_line import SerialBackend

    return SerialBackend()


def _remote_backend() -> Backend:
    from ego.backends.remote import RemoteBackend

    return RemoteBackend()


def _zenoh_backend() -> Backend:
    from ego.backends.zenoh_remote import ZenohBackend  # zenoh is imported only for zenoh://

    return ZenohBackend()


def _replay_backend() -> Backend:
    from ego.backends.replay import ReplayBackend  # mcap is imported only for a replay

    return ReplayBackend()


def register(scheme: str, factory: Callable[[], Backend]) -> None:
    """Serve ``scheme://...`` ports with the backend ``factory()`` makes."""
    _REGISTRY[scheme] = factory


def scheme_of(port: str) -> str:
    """The backend scheme of a port: ``sim``, ``tcp``, ``udp``... or ``serial``."""
    if port in _REGISTRY or port == "sim":  # a bare name: "sim"
        return port
    scheme, sep, _ = port.partition("://")
    if sep and (scheme in _REGISTRY or _declared(scheme) is not None):
        return scheme
    return "serial"  # a path, or a URL pyserial handles (socket://, loop://, spy://)


def _declared(scheme: str) -> Any:
    # Imported here: importlib.metadata costs the Overo ~4 MB and is needed only for a
    # scheme that is not built in.
    from importlib.metadata import entry_points

    found = entry_points(group=ENTRY_POINT_GROUP, name=scheme)
    return next(iter(found), None)


def find_backend(scheme: str) -> Backend:
    """The backend for ``scheme``: built in, registered, or declared by an installed package."""
    factory = _REGISTRY.get(scheme)
    if factory is None:
        declared = _declared(scheme)
        if declared is None:
            raise PortNotFoundError(
                f"no backend serves {scheme!r} ports: is the package that provides it "
                f"installed? (known: {', '.join(sorted(_REGISTRY))})"
            )
        factory = declared.load()
        _REGISTRY[scheme] = factory
    return factory()


def takes_option(port: str, name: str) -> bool:
    """Whether the backend of ``port`` names the option ``name`` among its own (a served
    robot's backend takes ``secret``; the emulator's and a serial port's do not)."""
    import inspect

    parameters = inspect.signature(find_backend(scheme_of(port)).open).parameters
    return name in parameters and parameters[name].kind is inspect.Parameter.KEYWORD_ONLY


def open_port(port: str, *, firmware: Firmware | None = None, **options: Any) -> Opened:
    """Open ``port`` with the backend its scheme names, passing it ``options``."""
    backend = find_backend(scheme_of(port))
    try:
        return backend.open(port, firmware=firmware, **options)
    except TypeError as exc:
        if "unexpected keyword argument" not in str(exc):
            raise
        raise ValueError(f"{scheme_of(port)} ports take no such option: {exc}") from None
