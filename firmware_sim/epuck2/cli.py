"""``python -m firmware_sim --robot epuck2 [--wifi|--bluetooth]``: serve an emulated
e-puck2 until killed, printing its pty path (or ``tcp://host:port``) first."""

from __future__ import annotations

import argparse
import signal
import sys
import threading
from types import FrameType

from firmware_sim.epuck2.emulator import Epuck2Emulator

__all__ = ["run"]


def run(args: argparse.Namespace) -> int:
    """Serve the e-puck2 the parsed options describe; the e-puck1's options are ignored."""
    try:
        emulator = Epuck2Emulator(
            args.world,
            seed=args.seed,
            wifi=args.wifi,
            bluetooth=args.bluetooth,
            port=args.wifi_port,
            latency_s=args.latency_ms / 1000,
            ground_module=args.ground_module_epuck2,
        )
    except (ValueError, OSError) as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    stop = threading.Event()

    def on_signal(signum: int, frame: FrameType | None) -> None:
        stop.set()

    try:
        signal.signal(signal.SIGTERM, on_signal)
        if emulator.wifi_address is not None:
            host, port = emulator.wifi_address
            print(f"tcp://{host}:{port}", flush=True)
        else:
            print(emulator.pty_path, flush=True)
        emulator.serve_forever(stop)
    except KeyboardInterrupt:
        pass
    finally:
        emulator.close()
    return 0
