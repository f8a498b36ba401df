"""Command line of the emulator: ``python -m firmware_sim`` and ``ego sim``."""

from __future__ import annotations

import argparse
import math
import signal
import sys
from collections.abc import Callable
from types import FrameType

from firmware_sim.dspic import FIRMWARES
from firmware_sim.faults import FAULT_KINDS, MAX_FAULT_S, FaultTimings, parse_fault
from firmware_sim.server import Emulator

__all__ = ["add_arguments", "build_parser", "main", "run"]


def _bounded(low: float, high: float, unit: str) -> Callable[[str], float]:
    """An argparse type: a finite number within ``low..high`` (NaN and inf refused)."""

    def parse(text: str) -> float:
        try:
            value = float(text)
        except ValueError:
            value = math.nan
        if not low <= value <= high:
            raise argparse.ArgumentTypeError(
                f"{text!r} is not a number within {low:g}..{high:g}{unit}"
            )
        return value

    return parse


def _hex_word(text: str) -> int:
    """An argparse type: a 16-bit word in hex (as V prints it)."""
    try:
        value = int(text, 16)
    except ValueError:
        value = -1
    if not 0 <= value <= 0xFFFF:
        raise argparse.ArgumentTypeError(f"{text!r} is not a 16-bit word in hex (0..FFFF)")
    return value


def _tcp_port(text: str) -> int:
    """An argparse type: a TCP port number, 0 (any free one) to 65535."""
    try:
        value = int(text)
    except ValueError:
        value = -1
    if not 0 <= value <= 0xFFFF:
        raise argparse.ArgumentTypeError(f"{text!r} is not a TCP port (0..65535)")
    return value


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--robot",
        choices=("epuck", "epuck2"),
        default="epuck",
        help="the robot: an e-puck's dsPIC (default), or a GCtronic e-puck2's main "
        "processor (asercom v2 over USB) or radio (--wifi, --bluetooth); the e-puck2 uses "
        "--world, --seed, --latency-ms and the options below",
    )
    parser.add_argument(
        "--wifi", action="store_true",
        help="e-puck2: the radio's WiFi TCP protocol (selector 15) instead of a pty",
    )  # fmt: skip
    parser.add_argument(
        "--bluetooth", action="store_true",
        help="e-puck2: asercom v2 over Bluetooth (selector 3, paced at 115200 baud)",
    )  # fmt: skip
    parser.add_argument(
        "--wifi-port", type=_tcp_port, default=1000, metavar="PORT",
        help="e-puck2 --wifi: the TCP port on 127.0.0.1 (default 1000, the firmware's; "
        "0 picks a free one)",
    )  # fmt: skip
    parser.add_argument(
        "--ground-module", dest="ground_module_epuck2", action="store_true",
        help="e-puck2: a ground-sensor module is fitted (default: none)",
    )  # fmt: skip
    parser.add_argument(
        "--firmware",
        choices=FIRMWARES,
        metavar="{" + ",".join(FIRMWARES) + "}",
        default="webots",
        help="which firmware to answer as (default: webots)",
    )
    parser.add_argument(
        "--baud",
        type=int,
        default=None,
        help="line rate used to pace the bytes (default: the firmware's own: 230400 for "
        "gctronic in Overo mode, 115200 over Bluetooth and for webots)",
    )
    parser.add_argument(
        "--processing-delay-us",
        type=_bounded(0, 1e6, " us"),
        default=0.0,
        help="extra dsPIC time per command, in microseconds (default: 0)",
    )
    parser.add_argument(
        "--fault",
        action="append",
        default=[],
        metavar="KIND=RATE|KIND@N",
        help=f"inject faults; KIND is one of {', '.join(FAULT_KINDS)}",
    )
    parser.add_argument(
        "--seed", type=int, default=None,
        help="seed for noise and faults (default: a fresh one each run)",
    )  # fmt: skip
    parser.add_argument(
        "--world",
        default=None,
        metavar="NAME|FILE",
        help="the world: a TOML world file, a Webots world (.wbt), or a built-in one "
        "(arena, line-track, maze, light; default arena)",
    )
    parser.add_argument(
        "--hardware-version",
        type=_hex_word,
        default=0xFFFF,
        metavar="HEX",
        help="the EEPROM word V reports as 'HW version: %%X' (default: FFFF, never written)",
    )
    parser.add_argument(
        "--rev13",
        action="store_true",
        help="an e-puck revision 1.3: I2C accelerometer (a/A answer zeros in Overo mode, "
        "where the Overo reads it over I2C), battery ADC",
    )
    parser.add_argument(
        "--selector",
        type=int,
        choices=range(16),
        metavar="0..15",
        default=None,
        help="the rotary selector; gctronic: 10 (default) is Overo mode on UART2, any other "
        "is Bluetooth mode",
    )
    parser.add_argument(
        "--no-ground-module",
        dest="ground_module",
        action="store_false",
        help="no floor-sensor board fitted: M reads 0xFFFF (Overo mode: M sends nothing "
        "anyway, and nothing answers at 0x60 on the Overo's I2C bus)",
    )
    parser.add_argument(
        "--no-dspic-work",
        dest="dspic_work",
        action="store_false",
        help="answer as soon as the line allows: no modelled firmware time (M's 3 ms I2C "
        "read of the floor sensors, A's 2 ms of floating point, K's calibration)",
    )
    parser.add_argument(
        "--latency-ms",
        type=_bounded(0, 10000, " ms"),
        default=0.0,
        help="extra delay each way, as a Bluetooth SPP link adds (a few ms; default 0)",
    )
    parser.add_argument(
        "--delay-s",
        type=_bounded(0, MAX_FAULT_S, " s"),
        default=0.1,
        help="length of a delay fault",
    )
    parser.add_argument(
        "--stall-s",
        type=_bounded(0, MAX_FAULT_S, " s"),
        default=1.0,
        help="length of a stall fault",
    )
    parser.add_argument(
        "--replug-s",
        type=_bounded(0, MAX_FAULT_S, " s"),
        default=0.3,
        help="length of a disconnect",
    )


def build_parser(prog: str = "python -m firmware_sim") -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog=prog,
        description="Emulated e-puck dsPIC on a pseudo-terminal. Prints the port's path "
        "as the first line of standard output, then serves until killed.",
    )
    add_arguments(parser)
    return parser


def run(args: argparse.Namespace) -> int:
    if args.robot == "epuck2":
        from firmware_sim.epuck2.cli import run as run_epuck2

        return run_epuck2(args)
    try:
        faults = [parse_fault(text) for text in args.fault]
        emulator = Emulator(
            args.firmware,
            baud=args.baud,
            processing_delay_s=args.processing_delay_us * 1e-6,
            faults=faults,
            seed=args.seed,
            timings=FaultTimings(args.delay_s, args.stall_s, args.replug_s),
            hardware_version=args.hardware_version,
            rev13=args.rev13,
            selector=args.selector,
            ground_module=args.ground_module,
            latency_s=args.latency_ms / 1000,
            dspic_work=args.dspic_work,
            world=args.world,
        )
    except ValueError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2

    def stop(signum: int, frame: FrameType | None) -> None:
        raise KeyboardInterrupt

    try:
        # Inside the try: a SIGTERM sent as soon as the path is read must still remove
        # the pty and its directory, and exit 0.
        signal.signal(signal.SIGTERM, stop)
        print(emulator.path, flush=True)
        emulator.serve_forever()
    except KeyboardInterrupt:
        pass
    finally:
        emulator.stop()
    return 0


def main(argv: list[str] | None = None, prog: str = "python -m firmware_sim") -> int:
    argv = sys.argv[1:] if argv is None else argv
    if argv[:1] == ["pipuck"]:  # the Pi-puck's I2C buses: firmware_sim.pipuck
        from firmware_sim.pipuck.cli import main as pipuck_main

        return pipuck_main(argv[1:], f"{prog} pipuck")
    return run(build_parser(prog).parse_args(argv))
