"""An emulated Pi-puck (GCtronic's Raspberry Pi Zero board for the e-puck): its I2C
devices, served to another process as ``/dev/i2c-N`` through an LD_PRELOAD shim, so
that smbus2's real ioctls (or C code on i2c-dev) run against it unmodified. Written
from the firmware and driver sources (PROTOCOL_NOTES.md), apart from ego.

Usage (the API is stable)::

    from firmware_sim.pipuck import PipuckEmulator

    with PipuckEmulator(robot="epuck2", buses="current", world=None,
                        virtual_time=False, seed=None,
                        bus_hz=100_000, paced=False) as emu:
        env = {**os.environ, **emu.environ()}   # LD_PRELOAD, the socket, the sysfs root
        subprocess.run([sys.executable, "my_controller.py"], env=env)
        emu.truth            # PipuckTruth: speeds, steps, LEDs, sounds, packets,
                             # checksum_errors, last_packet, last_was_stop,
                             # transactions, wire_s (time on the wire at bus_hz), ...
        emu.robot_bus        # 12 (legacy: 4); emu.board_bus: 11 (legacy: 3)
        emu.sysfs_root       # a directory standing for "/": the battery ADC's files
        emu.world            # the firmware_sim World the robot moves in
        emu.advance(0.5)     # virtual_time=True: let world time pass

    Faults and inputs: ``corrupt_next_reply(count=1)``, ``short_next_reply(length)``,
    ``set_present(0x1F, False)`` (nothing acknowledges there: EREMOTEIO),
    ``set_bus_present(12, False)`` (open fails: ENOENT), ``deny_access()`` (EACCES),
    ``set_battery(volts)``, ``press_button()``, ``remote_key(data)``.

``robot="epuck"`` is an e-puck1 with York's register firmware (and, ``rev13=True``,
its LSM330). ``build_shim()`` compiles the shim alone (cached by its source's hash).
The command line ``python -m firmware_sim pipuck`` serves one and prints the
environment to use.
"""

from firmware_sim.pipuck.emulator import SYSFS_ENV, PipuckEmulator
from firmware_sim.pipuck.shim import SOCKET_ENV, ShimBuildError, build_shim
from firmware_sim.pipuck.truth import PipuckTruth

__all__ = [
    "SOCKET_ENV",
    "SYSFS_ENV",
    "PipuckEmulator",
    "PipuckTruth",
    "ShimBuildError",
    "build_shim",
]
