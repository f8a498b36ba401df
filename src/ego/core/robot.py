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
from ego.core.robot_camera import CameraSlot
from ego.core.robot_devices import FamilyAttribute, RobotDevices
from ego.core.robot_step import Stepper
from ego.core.robot_stop import Parts
from ego.core.safety import OPEN_ROBOTS, install_signal_handlers
from ego.core.scheduler import Pacer, StepClock
from ego.devices.accelerometer import Accelerometer
from ego.devices.base import Device
from ego.devices.battery import Battery
from ego.devices.button import Button
from ego.devices.encoders import Encoders
from ego.devices.floor import FloorSensors
from ego.devices.gyro import Gyro
from ego.devices.leds import Leds
from ego.devices.light import LightSensors
from ego.devices.magnetometer import Magnetometer
from ego.devices.microphones import Microphones
from ego.devices.motors import Motors
from ego.devices.proximity import ProximitySensors
from ego.devices.selector import Selector
from ego.devices.sound import Speaker
from ego.devices.temperature import Temperature
from ego.devices.tof import TofSensor
from ego.errors import LinkLostError
from ego.i2c.bus import I2CBus, given_bus
from ego.i2c.side import OveroI2C
from ego.seam.channel import Channel, ChannelBase, TappedChannel, as_channel_base

if TYPE_CHECKING:
    from ego.camera import Camera, FrameSource
    from ego.core.ground_truth import GroundTruth
    from ego.core.scene import Scene
    from ego.seam.batch import Batch

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

    ``port`` is a serial port or any pyserial URL, ``"sim"`` for the emulator, or
    ``tcp://host:port`` / ``udp://host:port`` for a robot served by ``ego serve``; without
    one, ``EGO_PORT``, else ``/dev/ttyS0``. The port's backend (:mod:`ego.backends`) takes
    the ``options`` it declares (``firmware``, ``baudrate``, ``i2c_bus``, ``seed``,
    ``secret``...). ``channel`` instead steps through a
    :class:`~ego.seam.channel.Channel` opened elsewhere; ``i2c`` is the robot's own I2C bus
    (:mod:`ego.i2c`), by default the backend's.

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
        self.port, self._opened = _open(port, channel, options, environment)
        if i2c is not None:
            self._opened.i2c = given_bus(i2c)
        #: The way to the dsPIC: a serial Link, a RemoteChannel... (ego.seam.channel). Its
        #: lock is held by a step and by a stop from another thread (a dashboard's button),
        #: so that a stop comes between two steps' batches, never inside a step's recovery.
        self.channel: ChannelBase = as_channel_base(self._opened.channel)
        self._closed = False
        #: Paces the steps: the wall clock, or an emulator's virtual time (``--fast``), or a
        #: replay's clock at its speed.
        self.clock: Pacer = self._opened.pacer or StepClock()
        #: The robot's own I2C bus, read beside the batch (ego.i2c): opened at first need.
        self.i2c = OveroI2C(self._opened.i2c, self.port)
        # Everything the stop and the close need, held apart from the Robot (robot_stop).
        self._parts = Parts(self.channel, self.clock, self._opened, self.i2c)
        self._finalizer = weakref.finalize(self, self._parts.close)
        #: The device families (ego.core.robot_devices), one of each the table names.
        self.devices = RobotDevices(self.channel.profile, self.i2c)
        self.proximity.bind_calibration(self.calibrate_proximity)
        self.sound.bind_ascii(self.ascii_command)
        self._stepper: Stepper[Robot] = Stepper(
            self.devices, self._parts, self._opened.reply_clock or time.monotonic
        )
        self._camera = CameraSlot(self.port, self._parts, self._stepper.local_devices,
                                  camera_source, self._opened.camera)  # fmt: skip
        OPEN_ROBOTS.opened(self)
        if handle_signals:
            install_signal_handlers()
        log.info("robot on %s, firmware %s", self.port, self.channel.info.firmware)

    # The families (ego.devices), each named by its class's declaration.
    motors = FamilyAttribute(Motors)
    leds = FamilyAttribute(Leds)
    encoders = FamilyAttribute(Encoders)
    accelerometer = FamilyAttribute(Accelerometer)
    proximity = FamilyAttribute(ProximitySensors)
    floor = FamilyAttribute(FloorSensors)
    light = FamilyAttribute(LightSensors)
    microphones = FamilyAttribute(Microphones)
    battery = FamilyAttribute(Battery)
    # The e-puck2's (empty of members on an e-puck1: enabling them is refused).
    tof = FamilyAttribute(TofSensor)
    gyro = FamilyAttribute(Gyro)
    magnetometer = FamilyAttribute(Magnetometer)
    temperature = FamilyAttribute(Temperature)
    button = FamilyAttribute(Button)
    selector = FamilyAttribute(Selector)
    sound = FamilyAttribute(Speaker)

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

    @property
    def families(self) -> tuple[Device, ...]:
        """The device families, in the order Webots names their devices."""
        return self.devices.families

    def device(self, name: str) -> Device:
        """The family serving the Webots device ``name`` ("ps3", "left wheel motor"...)."""
        return self.devices.device(name)

    def family(self, name: str) -> Device:
        """The family the device table calls ``name``: ``robot.family("proximity")`` is
        ``robot.proximity``; a family added to the table is reached so."""
        return self.devices.family(name)

    @property
    def device_names(self) -> tuple[str, ...]:
        """Every Webots device name this robot answers to, by family, camera last."""
        return self.devices.device_names

    @property
    def camera(self) -> Camera:
        """The camera, opened at first use (the robot's V4L2 device, the emulator's, or remote)."""
        return self._camera.camera

    @property
    def open_camera(self) -> Camera | None:
        """The camera if something opened it, else None (looking does not open it)."""
        return self._camera.opened

    def step(self, ms: int) -> int:
        """Run one time step of ``ms`` milliseconds: send what is due, read, wait out the rest.

        Returns 0, or -1 once the link is lost for good (or the robot is closed), like
        Webots' ``step``.
        """
        if self._closed:
            return -1
        return self._stepper.step(ms, self.channel, self)

    @property
    def time_s(self) -> float:
        """Controller time: the sum of the steps taken, in seconds (Webots' getTime)."""
        return self._stepper.time_ms / 1000.0

    @property
    def steps(self) -> int:
        """How many steps ran to their end."""
        return self._stepper.steps

    @property
    def overruns(self) -> int:
        return self.clock.overruns

    def calibrate_proximity(self) -> None:
        """Calibrate the IR proximity sensors (``K``); see ProximitySensors.calibrate."""
        self._require_open()
        self.channel.calibrate_proximity()

    def ascii_command(self, letter: str, lines: int = 1) -> list[str]:
        """Send one ASCII command to the dsPIC and return its reply lines (after ``S``,
        ego's view of the motors and LEDs follows what the firmware did: RobotDevices)."""
        self._require_open()
        replies = self.channel.ascii_command(letter, lines)
        self.devices.heard_ascii(letter, self.channel.profile)
        return replies

    def _require_open(self) -> None:
        if self._closed or self._parts.lost:
            raise LinkLostError(f"{self.port}: the robot is {'closed' if self._closed else 'lost'}")

    def stop_actuators(self) -> None:
        """Stop both wheels and switch every LED off now, whatever ego believes their state.

        The batch ends with ``E`` so that the dsPIC answers: the stop is confirmed heard,
        and the speeds it reports must be zero.
        """
        self.motors.stop_request()
        self.leds.all_off()
        self._parts.stop_now()

    def send_stop(self) -> None:
        """Send the confirmed stop batch now, from any thread, between two steps' batches
        (ego's view of the actuators is left to the step: a guard keeps them stopped)."""
        self._parts.stop_now()

    def add_step_listener(self, listener: Callable[[Robot], None]) -> None:
        """Call ``listener(robot)`` after every step's exchange, in its slack before the
        wait (progress displays, loggers, the dashboard, a recorder)."""
        self._stepper.listeners.append(listener)

    def add_closer(self, closer: Callable[[], None]) -> None:
        """Call ``closer()`` when the robot closes, after its stop (a radio's session)."""
        self._opened.closers.append(closer)

    def add_step_guard(self, guard: Callable[[Robot], None]) -> None:
        """Call ``guard(robot)`` before every step's batch, after the controller's own
        commands: what it sets wins (a dashboard's stop and drive override the controller)."""
        self._stepper.guards.append(guard)

    def tap_channel(self, tap: Callable[[Batch, bytes], None]) -> None:
        """Hand ``tap`` every batch this robot exchanges, with its reply (a recording)."""
        self.channel = TappedChannel(self.channel, tap)

    def remove_step_hooks(self, hook: Callable[[Robot], None]) -> None:
        """Stop calling ``hook`` as a step listener or guard."""
        for hooks in (self._stepper.listeners, self._stepper.guards):
            while hook in hooks:
                hooks.remove(hook)

    def close(self) -> None:
        """Stop the motors, LEDs off, then close the port; calling it again does nothing."""
        if self._closed:
            return
        self._closed = True
        OPEN_ROBOTS.closed(self)
        if not self._parts.lost:
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
        state = "closed" if self._closed else ("lost" if self._parts.lost else "open")
        return f"<Robot {self.port} {self.channel.info.firmware} {state}>"


def _open(
    port: str | None,
    channel: Channel | None,
    options: dict[str, object],
    environment: Environment | None,
) -> tuple[str, Opened]:
    """The port's name and what its backend opened with ``options``, or the given ``channel``."""
    if channel is None:
        environment = environment or read_environment()
        name = resolve_port(port, environment.port)
        # Every option goes to the backend, None ones too: bound and checked there
        # (None: the backend's default), so a misspelt one is never dropped unseen.
        return name, open_port(name, environment=environment, **options)
    if given := sorted(name for name, value in options.items() if value is not None):
        raise ValueError(f"options {given} are for a port, not a given channel")
    return channel.name, Opened(channel)


# -- stopping robots however the controller ends --------------------------------------


def close_all_robots() -> None:
    """Close every robot of this process that is still open (each one stops first)."""
    OPEN_ROBOTS.close_all()
