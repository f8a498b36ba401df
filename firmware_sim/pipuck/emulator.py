"""An emulated Pi-puck: its I2C buses, served to other processes as ``/dev/i2c-N``.

>>> with PipuckEmulator(robot="epuck2", buses="current") as emu:  # doctest: +SKIP
...     env = {**os.environ, **emu.environ()}
...     subprocess.run([sys.executable, "controller.py"], env=env)
...     emu.truth.speeds

A process started with :meth:`PipuckEmulator.environ` in its environment loads the
LD_PRELOAD shim (``i2c_shim.c``, compiled on first use), and its ``open("/dev/i2c-N")``
reaches this emulator instead of the kernel: smbus2, or any C code using i2c-dev's
ioctls, read and write, runs unmodified. See the package docstring for the API.
"""

from __future__ import annotations

import os
import shutil
import tempfile
from pathlib import Path
from types import TracebackType

from firmware_sim.pipuck.board import write_battery
from firmware_sim.pipuck.gumstix import GumstixMcu
from firmware_sim.pipuck.machine import Options, PipuckMachine
from firmware_sim.pipuck.server import SocketServer
from firmware_sim.pipuck.shim import SOCKET_ENV, build_shim
from firmware_sim.pipuck.truth import PipuckTruth, truth_of
from firmware_sim.virtual_time import VirtualClock
from firmware_sim.world import World

__all__ = ["SYSFS_ENV", "PipuckEmulator"]

#: The variable naming the emulator's sysfs root (the battery's files live under it).
SYSFS_ENV = "FIRMWARE_SIM_SYSFS_ROOT"


class PipuckEmulator:
    """A Pi-puck carrying ``robot`` ("epuck2": the gumstix I2C mode; "epuck": York's
    firmware) with the bus numbers of ``buses`` ("current": robot 12, board 11;
    "legacy": 4 and 3), in ``world`` (a World, a built-in world's name or a world file;
    default: a fresh arena). ``virtual_time``: the world's clock moves only by
    :meth:`advance`. ``ground_module``, ``rev13`` (an e-puck1's LSM330), ``imu_address``
    (0x68 or 0x69), ``battery_v`` and ``aux_battery_v`` say what is fitted. ``bus_hz``
    is the Pi's I2C clock: each transaction's wire time at it is counted
    (``truth.wire_s``) and, with ``paced``, spent in real time.
    The socket's thread is started here and stopped and joined by :meth:`close`.
    """

    def __init__(
        self,
        robot: str = "epuck2",
        buses: str = "current",
        world: World | str | None = None,
        *,
        seed: int | None = None,
        virtual_time: bool = False,
        ground_module: bool = True,
        rev13: bool = True,
        imu_address: int = 0x68,
        battery_v: float = 3.9,
        aux_battery_v: float = 0.0,
        bus_hz: int = 100_000,
        paced: bool = False,
    ) -> None:
        if not 1_000 <= bus_hz <= 3_400_000:
            raise ValueError(f"an I2C clock of {bus_hz} Hz is outside 1 kHz..3.4 MHz")
        if imu_address not in (0x68, 0x69):
            raise ValueError(f"the MPU-9250 answers at 0x68 or 0x69, not {imu_address:#x}")
        if isinstance(world, str):
            from firmware_sim.worlds import load_world

            world = load_world(world, seed)
        self.world = world or World(seed=seed)
        self.clock: VirtualClock | None = None
        if virtual_time:
            self.clock = VirtualClock()
            self.world.use_clock(self.clock)
        options = Options(ground_module=ground_module, rev13=rev13, imu_address=imu_address,
                          bus_hz=bus_hz, paced=paced)  # fmt: skip
        self.machine = PipuckMachine(robot, buses, self.world, seed, options)
        self.shim = build_shim()
        self._dir = Path(tempfile.mkdtemp(prefix="ego-pipuck-"))
        self.socket_path = str(self._dir / "i2c.sock")
        #: A directory standing for "/": the battery ADC's sysfs files are under it.
        self.sysfs_root = self._dir / "root"
        self._battery = (battery_v, aux_battery_v)
        write_battery(self.sysfs_root, buses, battery_v, aux_battery_v)
        try:
            self._server: SocketServer | None = SocketServer(self.socket_path,
                                                             self.machine.session)  # fmt: skip
        except BaseException:
            shutil.rmtree(self._dir, ignore_errors=True)
            raise

    # -- what a subprocess needs ------------------------------------------------------

    @property
    def robot_bus(self) -> int:
        """The robot's bus number (12 current, 4 legacy)."""
        return self.machine.robot_bus

    @property
    def board_bus(self) -> int:
        """The Pi-puck board's bus number (11 current, 3 legacy)."""
        return self.machine.board_bus

    def environ(self) -> dict[str, str]:
        """The variables a process needs (add them to its environment): LD_PRELOAD with
        the shim first, the socket's path, and the sysfs root."""
        preload = [str(self.shim)]
        if os.environ.get("LD_PRELOAD"):
            preload.append(os.environ["LD_PRELOAD"])
        return {"LD_PRELOAD": ":".join(preload), SOCKET_ENV: self.socket_path,
                SYSFS_ENV: str(self.sysfs_root)}  # fmt: skip

    # -- ground truth ---------------------------------------------------------------

    @property
    def truth(self) -> PipuckTruth:
        with self.machine.lock:
            return truth_of(self.machine)

    def advance(self, seconds: float) -> None:
        """Let ``seconds`` of world time pass (``virtual_time`` only)."""
        if self.clock is None:
            raise RuntimeError("advance() needs PipuckEmulator(virtual_time=True)")
        with self.machine.lock:
            self.clock.advance(seconds)

    # -- faults and the robot's own inputs -------------------------------------------

    def _gumstix(self) -> GumstixMcu:
        if not isinstance(self.machine.mcu, GumstixMcu):
            raise ValueError("only the e-puck2's packet has a checksum to corrupt")
        return self.machine.mcu

    def corrupt_next_reply(self, count: int = 1) -> None:
        """The next ``count`` e-puck2 sensor replies carry a wrong XOR."""
        with self.machine.lock:
            self._gumstix().corrupt_next += count

    def short_next_reply(self, length: int) -> None:
        """The next e-puck2 sensor reply stops after ``length`` bytes (the rest reads
        0xFF, the idle bus)."""
        if not 0 <= length < 47:
            raise ValueError(f"a short reply has 0..46 bytes, not {length}")
        with self.machine.lock:
            self._gumstix().short_next = length

    def set_present(self, address: int, present: bool) -> None:
        """Make a device on the robot's bus stop (or resume) acknowledging its address:
        ``set_present(0x1F, False)`` is a robot in the wrong selector or unpowered."""
        with self.machine.lock:
            silent = self.machine.buses[self.robot_bus].silent
            if present:
                silent.discard(address)
            else:
                silent.add(address)

    def set_bus_present(self, number: int, present: bool) -> None:
        """Remove (or restore) ``/dev/i2c-<number>``: opens fail with ENOENT, as with I2C
        not enabled or the other kernel's numbering."""
        with self.machine.lock:
            if present:
                self.machine.missing.discard(number)
            else:
                self.machine.missing.add(number)

    def deny_access(self, denied: bool = True) -> None:
        """Opens fail with EACCES, as for a user outside the ``i2c`` group."""
        with self.machine.lock:
            self.machine.access_denied = denied

    def set_battery(self, volts: float, aux_volts: float | None = None) -> None:
        self._battery = (volts, self._battery[1] if aux_volts is None else aux_volts)
        write_battery(self.sysfs_root, self.machine.numbering, *self._battery)

    def press_button(self, pressed: bool = True) -> None:
        """The e-puck2's user button (bit 4 of the selector byte)."""
        with self.machine.lock:
            self._gumstix().robot.button = pressed

    def remote_key(self, data: int) -> None:
        """A TV remote's RC5 data byte reaches the e-puck2's receiver."""
        with self.machine.lock:
            robot = self._gumstix().robot
            robot.rc5 = (robot.rc5[0], robot.rc5[1], data & 0xFF)

    # -- lifetime -------------------------------------------------------------------

    def close(self) -> None:
        """Stop and join the socket's thread, remove the socket and the sysfs tree."""
        server, self._server = self._server, None
        if server is None:
            return
        try:
            server.close()
        finally:
            shutil.rmtree(self._dir, ignore_errors=True)

    def __enter__(self) -> PipuckEmulator:
        return self

    def __exit__(self, exc_type: type[BaseException] | None, exc: BaseException | None,
                 tb: TracebackType | None) -> None:  # fmt: skip
        self.close()
