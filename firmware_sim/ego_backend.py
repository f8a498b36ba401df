"""The ``sim`` backend of ego: the emulator behind a Robot, declared as an entry point.

This module is the one place where the emulator meets the library (it hands ego a
channel on the emulator's pty, the rendered camera, and the emulator's world as ego's
typed ground truth, :class:`EmulatorTruth`); every other module of ``firmware_sim`` is
written apart from ego, which is what makes the emulator a check on the library. ego
finds it through the ``ego.backends`` entry point group (pyproject.toml) and never
imports ``firmware_sim``.
"""

from __future__ import annotations

import contextlib
import errno
import os
from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np
from numpy.typing import NDArray

from ego.backends.serial_line import open_link
from ego.camera.source import GrantedFormat, PixelFormat, check_control_name
from ego.core.backend import BackendOptions, Opened, check
from ego.core.ground_truth import Box, Layout, TruePose
from ego.core.safety import OPEN_ROBOTS
from ego.errors import (
    CameraCaptureError,
    CameraError,
    LinkError,
    OutOfRangeError,
    WorldFileError,
)
from ego.i2c.bus import given_bus
from ego.nursery import before_owners_at_exit
from ego.seam.profile import DEFAULT_BAUD, Firmware
from ego.serial.link import LinkSettings
from ego.serial.transport import SerialTransport, check_baudrate
from firmware_sim.camera import SimulatedSource
from firmware_sim.cli import main as cli_main
from firmware_sim.epuck2.emulator import BLUETOOTH_SELECTOR, UART_BAUD, Epuck2Emulator
from firmware_sim.faults import FaultSpec, FaultTimings
from firmware_sim.scene import Scene
from firmware_sim.server import Emulator
from firmware_sim.swarm_scene import SwarmScene
from firmware_sim.true_devices import device_values
from firmware_sim.virtual_time import VirtualClock
from firmware_sim.world import World

__all__ = [
    "EmulatorTruth",
    "SimBackend",
    "SimOptions",
    "SimulatedCamera",
    "WorldTruth",
    "load_world",
]

# A program that exits with a Robot still open on an emulator: before Python waits for
# the threads, the emulators are told to end (firmware_sim.threads) and the robots are
# stopped (a finalizer, later). Here the robots are closed first, each stopping its
# wheels on an emulator still serving, as a real robot would be. threading runs these
# hooks last registered first, and this module always comes after firmware_sim.threads.
before_owners_at_exit(OPEN_ROBOTS.close_all)


def load_world(spec: str, seed: int | None) -> World:
    """The world a built-in name or a file names; ego's WorldFileError (one line naming
    the file and the reason) where the emulator refuses it."""
    from firmware_sim.worlds import load_world as load

    try:
        return load(spec, seed)
    except ValueError as exc:
        raise WorldFileError(str(exc)) from exc


class SimulatedCamera:
    """The emulator's rendered camera as an ego frame source: ego's types and errors."""

    def __init__(self, source: SimulatedSource) -> None:
        self.source = source

    def open(self, width: int, height: int, pixel_format: PixelFormat) -> GrantedFormat:
        try:
            return GrantedFormat(*self.source.open(width, height, pixel_format.value))
        except ValueError as exc:
            raise CameraCaptureError(errno.EINVAL, str(exc)) from exc

    def read_frame(self) -> bytes:
        try:
            return self.source.read_frame()
        except RuntimeError as exc:
            raise CameraError(str(exc)) from exc

    def set_control(self, name: str, value: int) -> int:
        return self.source.set_control(check_control_name(name), value)

    def set_fov_rad(self, fov_rad: float) -> float:
        return self.source.set_fov_rad(fov_rad)

    def close(self) -> None:
        self.source.close()

    def __repr__(self) -> str:
        return repr(self.source)


class WorldTruth:
    """The emulator's world as ego's :class:`~ego.core.ground_truth.TrueWorld`."""

    def __init__(self, world: World) -> None:
        self._world = world

    def layout(self) -> Layout:
        world = self._world
        half_x, half_y = world.arena.half_extents
        boxes = tuple(
            Box(block.x_m, block.y_m, *block.half_extents, block.yaw_rad, block.rgb)
            for block in world.blocks
        )
        return Layout(half_x, half_y, boxes, (world.lamp.x_m, world.lamp.y_m))

    def floor_reflectance(
        self, x_m: NDArray[np.float64], y_m: NDArray[np.float64]
    ) -> NDArray[np.float64]:
        return np.asarray(self._world.floor_reflectance(x_m, y_m), dtype=np.float64)

    def declared_devices(self) -> frozenset[str]:
        return self._world.declared_devices()

    def device_values(self, name: str) -> tuple[float, float, float]:
        return device_values(self._world, name)

    def touching(self) -> bool:
        return self._world.touching()

    @property
    def camera_size(self) -> tuple[int, int] | None:
        return self._world.camera_size

    @property
    def distance_travelled_m(self) -> float:
        return self._world.distance_travelled_m

    @property
    def closest_approach_m(self) -> float:
        return self._world.closest_approach_m


class EmulatorTruth:
    """The ground truth of a robot on the emulator (ego.core.ground_truth.GroundTruth).

    Beside ego's protocol it keeps the emulator's own objects for those who know them
    (tests, fault injection): :attr:`emulator` (None for a world given alone) and
    :attr:`world`.
    """

    def __init__(self, world: World, emulator: Emulator | Epuck2Emulator | None = None) -> None:
        self.world = world
        self.emulator = emulator
        self._true_world = WorldTruth(world)

    def pose(self) -> TruePose:
        pose = self.world.snapshot()
        return TruePose(pose.x_m, pose.y_m, pose.theta_rad)

    @property
    def true_world(self) -> WorldTruth:
        return self._true_world

    def __repr__(self) -> str:
        return f"<EmulatorTruth of {self.emulator or self.world!r}>"


class VirtualPacer:
    """Steps in the emulator's virtual time: each step moves the world on by its length at
    once, so the controller runs as fast as the CPU and the link allow."""

    def __init__(self, clock: VirtualClock) -> None:
        self._clock = clock
        self.overruns = 0
        self.worst_overrun_s = 0.0

    def begin(self) -> None:
        """Nothing to anchor: virtual time starts where the world is."""

    def wait(self, step_ms: float) -> bool:
        self._clock.advance(step_ms / 1000.0)
        return False

    def close(self) -> None:
        """Nothing to release."""


#: The robots the emulator models: the e-puck (its dsPIC, firmware_sim.server) and the
#: e-puck2 (its main processor's asercom v2, firmware_sim.epuck2).
ROBOTS = ("epuck", "epuck2")


def check_robot(robot: object) -> str | None:
    """``robot`` if it names a robot the emulator models; OutOfRangeError naming them else."""
    if robot is None or robot in ROBOTS:
        return robot
    raise OutOfRangeError(f"robot {robot!r} is not one of {', '.join(ROBOTS)}")


@dataclass(frozen=True, kw_only=True)
class SimOptions(BackendOptions):
    """The emulator's options; None: the default each names (the Emulator's own, for
    the options that go to it)."""

    #: The pty's line rate (None: the firmware's).
    baudrate: int | None = field(default=None, metadata=check(check_baudrate))
    #: The world's noise seed (None: a random one).
    seed: int | None = None
    #: How the link retries, resynchronises and reconnects (None: LinkSettings()).
    link_settings: LinkSettings | None = None
    #: The world moves only as the controller steps, as fast as it can (``ego run --fast``).
    virtual_time: bool | None = None
    #: A built-in world's name, a world file, or a World (None: the default arena).
    world: str | World | None = None
    #: Which robot: "epuck" (None: the default) or "epuck2" (its USB link; with
    #: ``selector=3`` its Bluetooth link, paced at 115200 baud).
    robot: str | None = field(default=None, metadata=check(check_robot))
    # The Emulator's own options (firmware_sim.server.Emulator), passed on when given:
    hardware_version: int | None = None
    rev13: bool | None = None
    selector: int | None = None
    ground_module: bool | None = None
    latency_s: float | None = None
    processing_delay_s: float | None = None
    faults: Sequence[FaultSpec] | None = None
    timings: FaultTimings | None = None
    dspic_work: bool | None = None
    #: The e-puck2 on its radio's WiFi (open_epuck2_wifi): ``robot="epuck2", wifi=True``.
    wifi: bool | None = None


#: The options that go to the Emulator as they are, when given.
_EMULATOR_OPTIONS = (
    "hardware_version", "rev13", "selector", "ground_module", "latency_s",
    "processing_delay_s", "faults", "timings", "dspic_work",
)  # fmt: skip


class SimBackend:
    """``Robot("sim", seed=..., firmware=...)``: a fresh emulator for this robot.

    Options (:class:`SimOptions`): ``seed`` (the world's), ``world`` (a built-in world's
    name or a world file: firmware_sim.worlds), ``baudrate`` (default: the firmware's
    line rate), ``link_settings``, ``virtual_time`` (the world moves only as the
    controller steps, as fast as it can: ``ego run --fast``), and the Emulator's own
    (``hardware_version``, ``rev13``, ``selector``, ``ground_module``, ``latency_s``...).
    In Overo mode the emulator's model of the robot's I2C bus goes in as the robot's own
    bus (``Opened.i2c``).
    """

    options: ClassVar[type[BackendOptions]] = SimOptions

    def open(self, port: str, options: BackendOptions) -> Opened:
        given = SimOptions.narrow(options)
        if given.wifi:
            return open_epuck2_wifi(given)
        if given.robot == "epuck2":
            return open_epuck2_serial(given)
        firmware = given.firmware
        name = (firmware or Firmware.WEBOTS).value
        emulator_options: dict[str, Any] = {
            key: value for key in _EMULATOR_OPTIONS if (value := getattr(given, key)) is not None
        }
        # A name or a file: ego's error (one line), before the emulator starts.
        emulator_options["world"] = given_world(given)
        emulator = Emulator(name, baud=given.baudrate, seed=given.seed, **emulator_options).start()
        try:
            transport = SerialTransport(
                emulator.path, emulator.baud, in_process_latency_s(emulator.latency_s)
            )
            channel = open_link(transport, firmware, given.link_settings)
        except BaseException:
            emulator.stop()
            raise
        world = emulator.world
        pacer = None
        if given.virtual_time:
            clock = VirtualClock()
            world.use_clock(clock)
            pacer = VirtualPacer(clock)
        camera = lambda: SimulatedCamera(SimulatedSource(world))  # noqa: E731
        i2c = None if emulator.i2c is None else given_bus(emulator.i2c)
        truth = EmulatorTruth(world, emulator)
        return Opened(
            channel, camera, truth, [emulator.stop], i2c=i2c, scene=Scene(world), pacer=pacer
        )

    @staticmethod
    def swarm_worlds(spec: str | None, seeds: Sequence[int | None]) -> list[Any]:
        """One world for each of ``seeds`` (its robot's noise seed), all made from one
        world file (a built-in's name, a path, None for the default arena), joined into
        one crowd: ego swarm's robots, each starting where the file places it, the others
        spread around the centre."""
        from firmware_sim.crowd import Crowd, spread_poses

        worlds: list[World] = [
            load_world(spec, seed) if spec else World(seed=seed) for seed in seeds
        ]
        poses = spread_poses(len(worlds), worlds[0].arena.half_size_m,
                             worlds[0].starts if spec else [])  # fmt: skip
        for world, pose in zip(worlds, poses, strict=True):
            world.start_at(pose)  # before they meet: nobody is in anybody's way yet
        Crowd(worlds)
        return worlds

    @staticmethod
    def swarm_supervisors(
        spec: str | None, worlds: Sequence[World], seed: int | None
    ) -> list[tuple[str, str, str, World]]:
        """The bodiless supervisors (``Robot { supervisor TRUE }``) of a swarm's world
        file: each one's DEF name (else its ``name`` field), its ``name`` field, its
        controller field, and a world of its own where it stands at its pose, in no robot's crowd:
        nobody senses it or bumps into it. None without a world file."""
        found: list[tuple[str, str, str, World]] = []
        if not spec or not worlds:
            return found
        for bodiless in worlds[0].supervisors:
            world = load_world(spec, seed)
            world.start_at(bodiless.pose)
            named = bodiless.def_name or bodiless.name
            found.append((named, bodiless.name, bodiless.controller, world))
        return found

    @staticmethod
    def swarm_channels(
        spec: str | None, worlds: Sequence[World]
    ) -> list[tuple[int | None, int | None]]:
        """Each member's emitter and receiver channels as its world file sets them: the
        robots' (``emitter_channel``, ``receiver_channel``; 1 where not given), then the
        bodiless supervisors' (their Emitter's and Receiver's ``channel``; None for a
        device it has not). Without a world file, every robot's are 1."""
        first = worlds[0] if worlds else None
        given = list(first.robot_radio) if spec and first is not None else []
        robots: list[tuple[int | None, int | None]] = [
            given[i] if i < len(given) else (1, 1) for i in range(len(worlds))
        ]
        supervisors = first.supervisors if spec and first is not None else []
        return robots + [(b.emitter_channel, b.receiver_channel) for b in supervisors]

    @staticmethod
    def swarm_scenes(
        worlds: Sequence[World], names: Sequence[str], bodiless: int = 0
    ) -> list[SwarmScene]:
        """Each member's scene of a swarm (firmware_sim.swarm_scene): ``worlds`` the robots'
        then the ``bodiless`` supervisors', ``names`` their names where the world file
        gives a robot none (its DEF name comes first)."""
        given = list(worlds[0].robot_names) if worlds else []
        robots = len(worlds) - bodiless
        named = [(given[i] if i < min(len(given), robots) else None) or name
                 for i, name in enumerate(names)]  # fmt: skip
        return [SwarmScene(worlds, named, me, bodiless) for me in range(len(worlds))]

    @staticmethod
    def main(argv: list[str], prog: str = "ego sim") -> int:
        """``ego sim ARGS``: the emulator's own command line."""
        return cli_main(argv, prog)

    @staticmethod
    @contextlib.contextmanager
    def pipuck_environment(
        robot: str | None, seed: int | None, world: str | None
    ) -> Iterator[dict[str, str]]:
        """An emulated Pi-puck carrying ``robot`` ("epuck2" by default, or "epuck") for as
        long as the context lasts, and the environment of a child process that reaches it
        as ``ego run --port pipuck`` would a real one (this process's, with the shim, its
        socket and ``EGO_SYSFS``): ``ego demo --pipuck``. A Pi-puck's I2C is reached only
        through a process started with it, never from this one. Its shim is compiled on
        first use: with no C compiler (a board as its guide installs it) that is a
        LinkError saying so, one line from ``ego``."""
        from firmware_sim.pipuck import PipuckEmulator, ShimBuildError

        spec = load_world(world, seed) if world else None
        try:
            emulator = PipuckEmulator(robot or "epuck2", "current", spec, seed=seed)
        except ShimBuildError as exc:
            raise LinkError(
                f"the emulated Pi-puck cannot start: {exc} (it is compiled on first use: "
                "install gcc, or try the demo on a PC)"
            ) from exc
        with emulator:
            sysfs = str(emulator.sysfs_root / "sys")
            yield {**os.environ, **emulator.environ(), "EGO_SYSFS": sysfs}


#: How late the host may let an in-process emulator's reply be. Its dsPIC answers from
#: threads of the controller's own process, which share the interpreter and the CPUs with
#: the controller and whatever else the machine runs: on a busy 2-core machine a reply has
#: come 30 ms late, four in a row, and a real dsPIC's 25 ms reply timeout ended ``ego
#: demo``. A real robot's link keeps its strict timeout (docs/protocol.md, Timing).
IN_PROCESS_SLACK_S = 0.25


def in_process_latency_s(each_way_s: float) -> float:
    """The reply latency of a link to an in-process emulator whose line adds
    ``each_way_s`` each way (a modelled Bluetooth link): both ways, plus the host's
    scheduling (:data:`IN_PROCESS_SLACK_S`)."""
    return IN_PROCESS_SLACK_S + 2 * each_way_s


def given_world(given: SimOptions) -> World | None:
    """The world the options name: a built-in's name or a file loaded (with the seed),
    a World as it is, None for the default arena."""
    spec = given.world
    return load_world(spec, given.seed) if isinstance(spec, str) else spec


def open_epuck2_wifi(given: SimOptions) -> Opened:
    """``Robot("sim", robot="epuck2", wifi=True)``: an emulated e-puck2 in selector 15, its
    radio's WiFi server on a free loopback port, opened as ``epuck2://127.0.0.1:PORT``
    (ego's WiFi backend, :mod:`ego.backends.epuck2`, exactly as a real robot's)."""
    from ego.backends.epuck2.camera import WifiCamera
    from ego.backends.epuck2.channel import Epuck2Channel
    from ego.errors import BackendOptionError
    from firmware_sim.epuck2 import Epuck2Emulator

    if given.robot not in (None, "epuck2"):
        raise BackendOptionError(
            f"sim option wifi=True is the e-puck2's radio (robot='epuck2'), not {given.robot!r}'s"
        )
    world = given_world(given)
    emulator = Epuck2Emulator(world or World(seed=given.seed), seed=given.seed, wifi=True,
                              port=0, ground_module=bool(given.ground_module))  # fmt: skip
    assert emulator.wifi_address is not None
    host, port = emulator.wifi_address
    try:
        channel = Epuck2Channel(f"epuck2://{host}:{port}", (host, port))
    except BaseException:
        emulator.close()
        raise
    camera = lambda: WifiCamera(channel)  # noqa: E731
    truth = EmulatorTruth(emulator.world)
    return Opened(
        channel, camera, truth, [emulator.close], remote=True, scene=Scene(emulator.world)
    )


def open_epuck2_serial(given: SimOptions) -> Opened:
    """``Robot("sim", robot="epuck2")``: an emulated e-puck2 on a pty, its USB link
    (selector 8) or, with ``selector=3``, its Bluetooth link (115200 baud, plus
    ``latency_s`` each way). ego finds the e-puck2 by its ``V`` as on a real port. It has
    no camera ego reads over these links (the WiFi link streams one)."""
    if given.firmware not in (None, Firmware.EPUCK2):
        raise OutOfRangeError(
            f"the emulated e-puck2 runs its own firmware ({Firmware.EPUCK2}), not "
            f"{given.firmware}: leave firmware unset (auto) or give {Firmware.EPUCK2}"
        )
    world = given_world(given)
    bluetooth = given.selector == BLUETOOTH_SELECTOR
    emulator = Epuck2Emulator(world, seed=given.seed, bluetooth=bluetooth,
                              latency_s=given.latency_s or 0.0,
                              ground_module=bool(given.ground_module))  # fmt: skip
    path = emulator.pty_path
    assert path is not None  # a serial mode always has its pty
    # USB CDC has no line rate: the port opens at ego's default, which it ignores.
    baud = given.baudrate or (UART_BAUD if bluetooth else DEFAULT_BAUD)
    try:
        transport = SerialTransport(path, baud, in_process_latency_s(given.latency_s or 0.0))
        channel = open_link(transport, given.firmware, given.link_settings)
    except BaseException:
        emulator.close()
        raise
    pacer = None
    if given.virtual_time:
        clock = VirtualClock()
        emulator.world.use_clock(clock)
        pacer = VirtualPacer(clock)
    truth = EmulatorTruth(emulator.world, emulator)
    return Opened(channel, None, truth, [emulator.close], scene=Scene(emulator.world),
                  pacer=pacer)  # fmt: skip
