"""``python -m firmware_sim pipuck``: serve an emulated Pi-puck until killed, printing
first the environment a process needs to reach it, as shell ``export`` lines:

    $ python -m firmware_sim pipuck --robot epuck2 > pipuck.env &
    $ . ./pipuck.env && python my_controller.py
"""

from __future__ import annotations

import argparse
import shlex
import signal
import sys
import threading
from types import FrameType

from firmware_sim.pipuck.emulator import PipuckEmulator
from firmware_sim.pipuck.shim import ShimBuildError

__all__ = ["build_parser", "main"]


def _address(text: str) -> int:
    try:
        return int(text, 0)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not an address (0x68, 0x69)") from None


def build_parser(prog: str) -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog=prog,
        description="Emulated Pi-puck I2C buses, reached through an LD_PRELOAD shim. "
        "Prints 'export NAME=value' lines for a process to use, then serves until killed.",
    )
    parser.add_argument("--robot", choices=("epuck2", "epuck"), default="epuck2",
                        help="e-puck2 in the gumstix I2C mode (default), or an e-puck1 "
                        "with York's register firmware")  # fmt: skip
    parser.add_argument("--buses", choices=("current", "legacy"), default="current",
                        help="bus numbers: robot 12, board 11 (default) or 4 and 3")  # fmt: skip
    parser.add_argument("--world", default=None, metavar="NAME|FILE",
                        help="a built-in world or a world file (default: arena)")  # fmt: skip
    parser.add_argument("--seed", type=int, default=None, help="seed for the noise")
    parser.add_argument("--no-ground-module", dest="ground_module", action="store_false",
                        help="no ground-sensor module at 0x60")  # fmt: skip
    parser.add_argument("--no-rev13", dest="rev13", action="store_false",
                        help="e-puck1: no LSM330 (a revision before 1.3)")  # fmt: skip
    parser.add_argument("--imu-address", type=_address, default=0x68,
                        help="e-puck2: the MPU-9250's address (0x68 default, or 0x69)")  # fmt: skip
    parser.add_argument("--battery-v", type=float, default=3.9,
                        help="the e-puck's battery voltage (default 3.9)")  # fmt: skip
    parser.add_argument("--bus-hz", type=int, default=100_000,
                        help="the Pi's I2C clock (default 100000)")  # fmt: skip
    parser.add_argument("--paced", action="store_true",
                        help="spend each transaction's wire time at --bus-hz")  # fmt: skip
    return parser


def main(argv: list[str], prog: str = "python -m firmware_sim pipuck") -> int:
    args = build_parser(prog).parse_args(argv)
    try:
        emulator = PipuckEmulator(args.robot, args.buses, args.world, seed=args.seed,
                                  ground_module=args.ground_module, rev13=args.rev13,
                                  imu_address=args.imu_address,
                                  battery_v=args.battery_v, bus_hz=args.bus_hz,
                                  paced=args.paced)  # fmt: skip
    except (ValueError, OSError, ShimBuildError) as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    stop = threading.Event()

    def on_signal(signum: int, frame: FrameType | None) -> None:
        stop.set()

    try:
        signal.signal(signal.SIGTERM, on_signal)
        for name, value in emulator.environ().items():
            print(f"export {name}={shlex.quote(value)}")
        print(f"# robot bus /dev/i2c-{emulator.robot_bus}, board bus "
              f"/dev/i2c-{emulator.board_bus}", flush=True)  # fmt: skip
        stop.wait()
    except KeyboardInterrupt:
        pass
    finally:
        emulator.close()
    return 0
