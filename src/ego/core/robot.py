"""The robot: owns the link, the devices and the step clock; stops safely however it ends."""

from __future__ import annotations

import logging
import threading
import time
import weakref
from collections.abc import Callable
from dataclasses import dataclass
from types import TracebackType
from typing import TYPE_CHECKING, Any

from ego.backends import Opened, open_port
from ego.core.channel import Channel, TappedChannel
from ego.core.environment import Environment, read_environment
from ego.core.ports import resolve_port
from ego.core.safety import OPEN_ROBOTS, install_signal_handlers, send_stop
from ego.core.scheduler import Pacer, StepClock
from ego.core.transaction import run_step
from ego.devices.accelerometer import Accelerometer
from ego.devices.base import MAX_PERIOD_MS, Device, Sensor, check_int
from ego.devices.battery import Battery
from ego.devices.encoders import Encoders
from ego.devices.floor import FloorSensors
from ego.devices.leds import Leds
from ego.devices.light import LightSensors
from ego.devices.microphones import Microphones
from ego.devices.motors import Motors
from ego.devices.proximity import ProximitySensors
from ego.errors import (
    CameraError,
    EgoError,
    LinkLostError,
    UnknownDeviceError,
)
from ego.i2c.bus import I2CBus, given_bus
from ego.i2c.side import OveroI2C, run_i2c_step

if TYPE_CHECKING:
    from ego.camera import Camera, FrameSource
    from ego.core.scene import Scene
    from ego.serial.protocol import Batch

__all__ = ["SIM_PORT", "Robot", "close_all_robots"]

log = logging.getLogger(__name__)

#: The port name that starts the built-in dsPIC emulator.
SIM_PORT = "sim"


class Robot:
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
    through a :class:`~ego.core.channel.Channel` opened elsewhere. ``i2c`` is the robot's own
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
        if channel is None:
            environment = environment or read_environment()
            self.port = resolve_port(port, environment.port)
            # Every option goes to the backend, None ones too: bound and checked there
            # (None: the backend's default), so a misspelt one is never dropped unseen.
            self._opened = open_port(self.port, environment=environment, **options)
        elif given := sorted(name for name, value in options.items() if value is not None):
            raise ValueError(f"options {given} are for a port, not a given channel")
        else:
            self.port = channel.name
            self._opened = Opened(channel)
        if i2c is not None:
            self._opened.i2c = given_bus(i2c)
        #: The way to the dsPIC: a serial Link, a RemoteChannel... (ego.core.channel).
        self.link: Channel = self._opened.channel
        self._closed = False
        self._lost = False
        #: Paces the steps: the wall clock, or an emulator's virtual time (``--fast``), or a
        #: replay's clock at its speed.
        self.clock: Pacer = self._opened.pacer or StepClock()
        self._reply_clock = self._opened.reply_clock or time.monotonic
        # Everything the stop and the close need, held apart from the Robot so that a
        # finalizer can stop the wheels when the Robot is dropped without close(), or
        # when the interpreter exits with it still open.
        #: The robot's own I2C bus, read beside the batch (ego.i2c): opened at first need.
        self.i2c = OveroI2C(self._opened.i2c, self.port)
        self._parts = _Parts(self.link, self.clock, self._opened, self.i2c)
        self._finalizer = weakref.finalize(self, self._parts.close)
        profile = self.link.profile
        self.motors = Motors(profile)
        self.leds = Leds(profile)
        self.encoders = Encoders(profile)
        self.accelerometer = Accelerometer(profile)
        self.proximity = ProximitySensors(profile)
        self.floor = FloorSensors(profile)
        self.light = LightSensors(profile)
        self.microphones = Microphones(profile)
        self.battery = Battery(profile)
        self.proximity.bind_calibration(self.calibrate_proximity)
        #: The device families, in the order Webots names their devices.
        self.families: tuple[Device, ...] = (
            self.motors,
            self.leds,
            self.encoders,
            self.accelerometer,
            self.proximity,
            self.floor,
            self.light,
            self.microphones,
            self.battery,
        )
        #: What each step's transaction runs over (ego.core.transaction).
        self._step_parts = tuple(part for family in self.families for part in family.parts)
        for part in self._step_parts:
            if isinstance(part, Sensor):
                part.bind_i2c(self.i2c)
        #: Devices the step clock schedules on this side of the link (the camera, once
        #: opened): each is updated with the step's time.
        self._local_devices: list[Camera] = []
        self._camera: Camera | None = None
        self._camera_source = camera_source
        self._time_ms = 0
        self.steps = 0
        self._listeners: list[Callable[[Robot], None]] = []
        self._guards: list[Callable[[Robot], None]] = []
        #: Held while a step talks to the robot: another thread that must reach the dsPIC
        #: at once (a dashboard's stop button) takes it between two steps' batches.
        self.link_lock = threading.RLock()
        OPEN_ROBOTS.opened(self)
        if handle_signals:
            install_signal_handlers()
        log.info("robot on %s, firmware %s", self.port, self.link.info.firmware)

    # -- devices ---------------------------------------------------------------------

    @property
    def closed(self) -> bool:
        """Whether close() was called (or the robot never opened)."""
        return self._closed

    @property
    def remote(self) -> bool:
        """Whether this robot is driven over a network (through ``ego serve``)."""
        return self._opened.remote

    @property
    def emulator(self) -> Any:
        """The emulator behind a simulated robot (its world is the ground truth), else None."""
        return self._opened.ground_truth

    @property
    def scene(self) -> Scene | None:
        """The simulated world's solids for a Webots Supervisor; None on a real robot."""
        return self._opened.scene

    @property
    def camera(self) -> Camera:
        """The camera, opened at first use (the robot's V4L2 device, the emulator's, or remote)."""
        if self._camera is None:
            from ego.camera import Camera

            self._camera = Camera(source=self._camera_source or self._default_camera_source())
            self._parts.camera = self._camera
            self._local_devices.append(self._camera)
        return self._camera

    @property
    def open_camera(self) -> Camera | None:
        """The camera if something opened it, else None (looking does not open it)."""
        return self._camera

    def _default_camera_source(self) -> FrameSource:
        if self._opened.camera is None:
            raise CameraError(f"this robot has no camera ({self.port}; EGO_CAMERA=none?)")
        return self._opened.camera()

    def device(self, name: str) -> Device:
        """The family serving the Webots device ``name`` ("ps3", "left wheel motor"...).

        The device table (:mod:`ego.devices.table`) says which family; the family says
        whether the connected firmware has it (ps8, ps9: the Overo's only).
        """
        from ego.devices.table import CAMERA, find

        found = find(name)
        if found is not None and found.webots_device and found.family != CAMERA:
            family: Device = getattr(self, found.family)
            if name in family.member_names:
                return family
        raise UnknownDeviceError(
            f"no device named {name!r}; valid names: {', '.join(self.device_names)}"
        )

    @property
    def device_names(self) -> tuple[str, ...]:
        """Every Webots device name this robot answers to, by family, camera last."""
        from ego.devices.table import CAMERA, DEVICES

        rank = {id(family): i for i, family in enumerate(self.families)}
        served = sorted(
            (rank[id(family)], s.index, s.name)
            for s in DEVICES
            if s.family != CAMERA and s.name in (family := getattr(self, s.family)).member_names
        )
        return (*(name for _, _, name in served), *(s.name for s in DEVICES if s.family == CAMERA))

    # -- ASCII commands --------------------------------------------------------------

    def calibrate_proximity(self) -> None:
        """Calibrate the IR proximity sensors (``K``); see ProximitySensors.calibrate."""
        self._require_open()
        self.link.calibrate_proximity()

    def ascii_command(self, letter: str, lines: int = 1) -> list[str]:
        """Send one ASCII command to the dsPIC and return its reply lines.

        ``S`` (stop) differs between the firmwares (docs/protocol.md, quirk "S"): the
        stock one stops the wheels and the ring LEDs but keeps echoing the old speeds in
        ``E``; Webots' also clears that echo and the body and front LEDs. ego's own view of
        the motors and LEDs follows what the connected firmware did, and on the stock
        firmware a ``D 0 0`` goes with the next batch so that ``E`` echoes the truth:
        otherwise ego's speed check would see a mismatch and send the old speeds again.
        """
        self._require_open()
        replies = self.link.ascii_command(letter, lines)
        if letter.upper() == "S":
            stop = self.link.profile.ascii_stop
            self.motors.stopped_by_firmware(resend=not stop.clears_echo)
            self.leds.switched_off(stop.leds)
        return replies

    def _require_open(self) -> None:
        if self._closed or self._lost:
            raise LinkLostError(f"{self.port}: the robot is {'closed' if self._closed else 'lost'}")

    # -- time ------------------------------------------------------------------------

    @property
    def time_s(self) -> float:
        """Controller time: the sum of the steps taken, in seconds (Webots' getTime)."""
        return self._time_ms / 1000.0

    @property
    def overruns(self) -> int:
        return self.clock.overruns

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

    def tap_link(self, tap: Callable[[Batch, bytes], None]) -> None:
        """Hand ``tap`` every batch this robot exchanges, with its reply (a recording)."""
        self.link = TappedChannel(self.link, tap)

    def remove_step_hooks(self, hook: Callable[[Robot], None]) -> None:
        """Stop calling ``hook`` as a step listener or guard."""
        for hooks in (self._listeners, self._guards):
            while hook in hooks:
                hooks.remove(hook)

    def step(self, ms: int) -> int:
        """Run one time step of ``ms`` milliseconds: send what is due, read, wait out the rest.

        Returns 0, or -1 once the link is lost for good (or the robot is closed), like
        Webots' ``step``.
        """
        if self._closed or self._lost:
            return -1
        step_ms = check_int("time step", ms, 1, MAX_PERIOD_MS, " ms")
        self.clock.begin()
        now = self._time_ms
        for guard in self._guards:
            guard(self)
        try:
            with self.link_lock:
                run_step(self._step_parts, self.link, now, self._restarted, self._reply_clock)
            # Also where a network channel says its session ended with nothing to send.
            self.link.waiting_until(time.monotonic() + step_ms / 1000.0)
        except LinkLostError as exc:
            ended = getattr(exc, "expected", False)  # a replay's end: over, not broken
            log.log(logging.INFO if ended else logging.ERROR, "link lost for good: %s", exc)
            self._lost = self._parts.lost = True
            return -1
        # Beside the batch: what the firmware leaves on the Overo's I2C bus (its own lock).
        run_i2c_step(self._step_parts, self.i2c, now)
        for local in self._local_devices:  # captured here, not over the link: the camera
            local.update(now)
        self._time_ms += step_ms
        self.steps += 1
        # Listeners run in the step's slack, before its wait: what they cost is hidden
        # in the wait rather than added to the step (a dashboard, a recorder).
        for listener in self._listeners:
            listener(self)
        self.clock.wait(step_ms)
        return 0

    def _restarted(self) -> None:
        profile = self.link.profile
        for family in self.families:
            family.set_profile(profile)
            for part in family.parts:
                part.reset()

    # -- safe stop -------------------------------------------------------------------

    def stop_actuators(self) -> None:
        """Stop both wheels and switch every LED off now, whatever ego believes their state.

        The batch ends with ``E`` so that the dsPIC answers: the stop is confirmed heard,
        and the speeds it reports must be zero.
        """
        self.motors.stop_request()
        self.leds.all_off()
        with self.link_lock:
            send_stop(self.link)

    def send_stop(self) -> None:
        """Send the confirmed stop batch now, from any thread, between two steps' batches
        (ego's view of the actuators is left to the step: a guard keeps them stopped)."""
        with self.link_lock:
            send_stop(self.link)

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
        return f"<Robot {self.port} {self.link.info.firmware} {state}>"


# -- stopping robots however the controller ends --------------------------------------


@dataclass
class _Parts:
    """What a robot must stop and release, without a reference back to the Robot."""

    link: Channel
    clock: Pacer
    opened: Opened
    i2c: OveroI2C
    camera: Camera | None = None
    lost: bool = False

    def close(self) -> None:
        """Stop the wheels and LEDs (unless the link is lost), then release everything."""
        if not self.lost:
            try:
                send_stop(self.link)
            except (EgoError, OSError) as exc:
                log.error("could not stop the robot's actuators: %s", exc)
        if self.camera is not None:
            self.camera.close()
        self.clock.close()
        self.i2c.close()
        self.link.close()
        self.opened.close()


def close_all_robots() -> None:
    """Close every robot of this process that is still open (each one stops first)."""
    OPEN_ROBOTS.close_all()
