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
``epuck2``    a GCtronic e-puck2 over WiFi (``epuck2://HOST[:PORT]``, selector 15):
              :mod:`ego.backends.epuck2`
``pipuck``    a robot carrying a Pi-puck, driven over I2C by ego on the Pi (``pipuck``),
              found through the ``ego.backends`` entry point: :mod:`ego.backends.pipuck`
============  ==========================================================================

Each backend opens a :class:`~ego.seam.channel.Channel` (the seam under ``Robot``) and takes
the options it knows: a serial port its baud rate and link settings, the emulator its
seed, the network its secret. Beside the channel it may hand in the robot's own I2C bus
(:class:`~ego.i2c.bus.I2CAccess`, opened at first need), where the stock firmware leaves
the ground module and a rev 1.3's accelerometer to the Overo: the Overo's
``/dev/i2c-3`` on its own UART, the emulator's model of the bus for ``sim``. A new
backend (Bluetooth discovery, a distributed engine, another robot) is one module with a
class that has :meth:`Backend.open` and declares its options (a frozen
:class:`BackendOptions` dataclass, :mod:`ego.core.backend`), registered under the
``ego.backends`` entry point group or with :func:`register`; nothing in ``Robot`` changes.

A port's options are bound and checked in one place, :func:`bind_options`, before its
backend opens it (python-can's ``can.util.load_config``): a name the backend does not
declare is refused with :class:`~ego.errors.BackendOptionError` naming the scheme, the
option and the options that scheme takes; a value of the wrong type is refused too; a
value of None stands for the backend's default. The environment's defaults
(:mod:`ego.core.environment`) fill in what the caller left out.
"""

from __future__ import annotations

from ego.core.backend import Backend, BackendOptions, Opened, check
from ego.core.registry import (
    ENTRY_POINT_GROUP,
    bind_options,
    find_backend,
    open_port,
    option_names,
    register,
    registered,
    scheme_of,
    takes_option,
)

__all__ = [
    "BUILT_IN",
    "ENTRY_POINT_GROUP",
    "Backend",
    "BackendOptions",
    "Opened",
    "bind_options",
    "check",
    "find_backend",
    "open_port",
    "option_names",
    "register",
    "registered",
    "scheme_of",
    "takes_option",
]

#: The built-in backends, by scheme: each module is imported only when a port of its
#: scheme is first opened (zenoh and mcap load only for their own ports), as
#: python-can's ``BACKENDS``. This is the one place that names them.
BUILT_IN: dict[str, str] = {
    "serial": "ego.backends.serial_line:SerialBackend",
    "tcp": "ego.backends.remote:RemoteBackend",
    "udp": "ego.backends.remote:RemoteBackend",
    "unix": "ego.backends.remote:RemoteBackend",
    "replay": "ego.backends.replay:ReplayBackend",
    "zenoh": "ego.backends.zenoh_remote:ZenohBackend",
    "epuck2": "ego.backends.epuck2:Epuck2Backend",
}

for _scheme, _target in BUILT_IN.items():
    register(_scheme, _target)
