"""The robot: owns the link, the devices and the step clock; stops safely however it ends."""

from __future__ import annotations

import logging
import time
import weakref
from collections.abc import Callable
from types import TracebackType
from typing import TYPE_CHECKING

from ego.core.backend import Opened
from ego.core.environment import Environment, read_environment
from ego.core.ports import resolve_port
from ego.core.registry import open_port
from ego.core.robot_camera import CameraWiring
from ego.core.robot_devices import DeviceWiring
from ego.core.robot_step import Stepping
from ego.core.robot_stop import Parts, SafeStop
from ego.core.safety import OPEN_ROBOTS, install_signal_handlers
from ego.core.scheduler import Pacer, StepClock
from ego.i2c.bus import I2CBus, given_bus
from ego.i2c.side import OveroI2C
from ego.seam.channel import Channel, ChannelBase, TappedChannel, as_channel_base

if TYPE_CHECKING:
    from ego.camera import FrameSource
    from ego.core.ground_truth import GroundTruth
    from ego.core.scene import Scene
    from ego.seam.batch import Batch

__all__ = ["SIM_PORT", "Robot", "close_all_robots"]

log = logging.getLogger(__name__)

#: The port name that starts the built-in dsPIC emulator.
SIM_PORT = "sim"


class Robot(DeviceWiring, CameraWiring, Stepping, SafeStop):
    """An e-puck: its devices, one batch of commands per time step, and a safe stop.

    >>> import ego
    >>> with ego.Robot("sim") as robot:                  # doctest: +SKIP
    ...     robot.proximity.enable(64)
    ...     robot.motors.set_speed(300, 300)
    ...     while robot.step(64) != -1 and robot.time_s < 2:
    ...         if max(robot.proximity.values) > 300:
    ...             robot.motors.set_speed(-200, 200)

    ``port`` is a serial port or any pyserial URL, ``"sim"`` for the built-in emulator,
    or ``tcp://host:port`` / ``udp://host:port`` for a robot served by ``ego serve``;
    without one, ``EGO_PORT``, else ``/dev/ttyS0``. The port's backend
    (:mod:`ego.backends`) takes the ``options`` it knows: ``firmware`` for all (None:
    detect it), ``baudrate``, ``link_settings``, ``camera_device`` and ``i2c_bus`` (the
    robot's own I2C bus: a number, a ``/dev/i2c-N`` path, or "none") for a serial port,
    ``seed`` for the emulator, ``secret`` for the network. ``channel`` instead steps
    through a :class:`~ego.seam.channel.Channel` opened elsewhere. ``i2c`` is the robot's own
    I2C bus, where the stock firmware in Overo mode leaves the ground sensors and a rev
    1.3's accelerometer (:mod:`ego.i2c`); by default the backend's (the Overo's
    ``/dev/i2c-3`` on its own UART, the emulator's for ``"sim"``).

    Leaving the ``with`` block, an exception, or dropping the Robot stops the motors and
    turns the LEDs off before the port closes. ``handle_signals`` also turns every
    signal that would end the process into an exit that does the same; it changes the
    process's signal handlers, so it is off unless asked for (``ego run`` asks).
    """

    def __init__(
        self,
        port: str | None = None,
        *,
        channel: Channel | None = None,
        camera_source: FrameSource | None = None,
        i2c: I2CBus | None = None,
        handle_signals: bool = False,
        environment: Environment | None = None,
        **options: object,
    ) -> None:
        self._closed = True  # until the channel is up, close() has nothing to stop
        self._opened = self._open(port, channel, options, environment)
        if i2c is not None:
            self._opened.i2c = given_bus(i2c)
        #: The way to the dsPIC: a serial Link, a RemoteChannel... (ego.seam.channel). Its
        #: lock is held by a step and by a stop from another thread (a dashboard's button),
        #: so that a stop comes between two steps' batches, never inside a step's recovery.
        self.channel: ChannelBase = as_channel_base(self._opened.channel)
        self._closed = False
        self._lost = False
        #: Paces the steps: the wall clock, or an emulator's virtual time (``--fast``), or a
        #: replay's clock at its speed.
        self.clock: Pacer = self._opened.pacer or StepClock()
        self._reply_clock = self._opened.reply_clock or time.monotonic
        #: The robot's own I2C bus, read beside the batch (ego.i2c): opened at first need.
        self.i2c = OveroI2C(self._opened.i2c, self.port)
        # Everything the stop and the close need, held apart from the Robot (robot_stop).
        self._parts = Parts(self.channel, self.clock, self._opened, self.i2c)
        self._finalizer = weakref.finalize(self, self._parts.close)
        self._wire_devices()
        self._local_devices = []
        self._camera = None
        self._camera_source = camera_source
        self._time_ms = 0
        self.steps = 0
        self._listeners: list[Callable[[Robot], None]] = []
        self._guards: list[Callable[[Robot], None]] = []
        OPEN_ROBOTS.opened(self)
        if handle_signals:
            install_signal_handlers()
        log.info("robot on %s, firmware %s", self.port, self.channel.info.firmware)

    def _open(
        self,
        port: str | None,
        channel: Channel | None,
        options: dict[str, object],
        environment: Environment | None,
    ) -> Opened:
        """Open ``port`` through its backend with ``options``, or take the given ``channel``."""
        if channel is None:
            environment = environment or read_environment()
            self.port = resolve_port(port, environment.port)
            # Every option goes to the backend, None ones too: bound and checked there
            # (None: the backend's default), so a misspelt one is never dropped unseen.
            return open_port(self.port, environment=environment, **options)
        if given := sorted(name for name, value in options.items() if value is not None):
            raise ValueError(f"options {given} are for a port, not a given channel")
        self.port = channel.name
        return Opened(channel)

    @property
    def closed(self) -> bool:
        """Whether close() was called (or the robot never opened)."""
        return self._closed

    @property
    def remote(self) -> bool:
        """Whether this robot is driven over a network (through ``ego serve``)."""
        return self._opened.remote

    @property
    def ground_truth(self) -> GroundTruth | None:
        """What the simulator behind this robot knows of it and its world (its true pose,
        the world's layout: :mod:`ego.core.ground_truth`); None on a real robot."""
        return self._opened.ground_truth

    @property
    def scene(self) -> Scene | None:
        """The simulated world's solids for a Webots Supervisor; None on a real robot."""
        return self._opened.scene

    # -- hooks -----------------------------------------------------------------------

    def add_step_listener(self, listener: Callable[[Robot], None]) -> None:
        """Call ``listener(robot)`` after every step's exchange, in its slack before the
        wait (progress displays, loggers, the dashboard, a recorder)."""
        self._listeners.append(listener)

    def add_closer(self, closer: Callable[[], None]) -> None:
        """Call ``closer()`` when the robot closes, after its stop (a radio's session)."""
        self._opened.closers.append(closer)

    def add_step_guard(self, guard: Callable[[Robot], None]) -> None:
        """Call ``guard(robot)`` before every step's batch, after the controller's own
        commands: what it sets wins (a dashboard's stop and drive override the controller)."""
        self._guards.append(guard)

    def tap_channel(self, tap: Callable[[Batch, bytes], None]) -> None:
        """Hand ``tap`` every batch this robot exchanges, with its reply (a recording)."""
        self.channel = TappedChannel(self.channel, tap)

    def remove_step_hooks(self, hook: Callable[[Robot], None]) -> None:
        """Stop calling ``hook`` as a step listener or guard."""
        for hooks in (self._listeners, self._guards):
            while hook in hooks:
                hooks.remove(hook)

    def _run_guards(self) -> None:
        for guard in self._guards:
            guard(self)

    def _run_listeners(self) -> None:
        for listener in self._listeners:
            listener(self)

    # -- closing ---------------------------------------------------------------------

    def close(self) -> None:
        """Stop the motors, LEDs off, then close the port; calling it again does nothing."""
        if self._closed:
            return
        self._closed = True
        OPEN_ROBOTS.closed(self)
        if not self._lost:
            # ego's own view of the actuators follows the stop the finalizer sends.
            self.motors.stop_request()
            self.leds.all_off()
        self._finalizer()

    def __enter__(self) -> Robot:
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        self.close()

    def __repr__(self) -> str:
        state = "closed" if self._closed else ("lost" if self._lost else "open")
        return f"<Robot {self.port} {self.channel.info.firmware} {state}>"


# -- stopping robots however the controller ends --------------------------------------


def close_all_robots() -> None:
    """Close every robot of this process that is still open (each one stops first)."""
    OPEN_ROBOTS.close_all()
