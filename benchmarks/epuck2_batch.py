"""The e-puck2's batch strategy, measured: e-puck1 commands against the all-sensors packet.

For each set of enabled sensors, over the emulated e-puck2's USB link (unpaced pty, the
firmware's own sleeps) and its Bluetooth link (paced at 115200 baud), one step's reads go
three ways: as the e-puck1 commands (``N``, ``O``, ``Q``, ``g``, ``-0x0D``...), as one
``-0x08`` "all sensors" packet, and as :func:`ego.serial.protocol.encode_batch` chooses
(by ``Profile.cost_s``). The table gives each way's bytes (sent + received) and median
round trip; the profile's docstring (``EPUCK2_USB``) says what was chosen from it.

    python -m benchmarks.epuck2_batch [--rounds N]
"""

from __future__ import annotations

import argparse
import statistics
import time
from collections.abc import Sequence
from dataclasses import replace
from types import MappingProxyType

from ego.seam.batch import Batch
from ego.seam.profile import DEFAULT_BAUD, Profile
from ego.serial import Command, Link, Request, SerialTransport, encode_batch
from firmware_sim.epuck2.emulator import UART_BAUD, Epuck2Emulator

__all__ = ["SETS", "measure", "run"]

#: The enabled-sensor sets measured, each by the commands its families read.
SETS: dict[str, tuple[Command, ...]] = {
    "ps": (Command.PROXIMITY,),
    "ps+enc": (Command.PROXIMITY, Command.GET_STEPS),
    "ps+ls+enc": (Command.PROXIMITY, Command.LIGHT, Command.GET_STEPS),
    "ps+enc+tof+gyro": (Command.PROXIMITY, Command.GET_STEPS, Command.TOF, Command.GYRO_RAW),
    "all but acc": (Command.PROXIMITY, Command.LIGHT, Command.GET_STEPS, Command.TOF,
                    Command.GYRO_RAW, Command.MICROPHONES_4, Command.BATTERY),
    "ps+enc+acc": (Command.PROXIMITY, Command.GET_STEPS, Command.ACCELEROMETER_RAW),
}  # fmt: skip


_PAYLOAD = (0, 300, 300, 0, *([0] * 12), 0)
#: The actuator batches compared: e-puck1 commands (and -0x0A) against "all actuators",
#: each confirmed by an E as ego's motors are.
ACTUATORS: dict[str, tuple[tuple[Request, ...], tuple[Request, ...]]] = {
    "speeds": ((Request(Command.SET_SPEED, (300, 300)), Request(Command.GET_SPEED)),
               (Request(Command.ALL_ACTUATORS, _PAYLOAD), Request(Command.GET_SPEED))),
    "speeds+6 LEDs+RGB": (
        (Request(Command.SET_SPEED, (300, 300)),
         *(Request(Command.SET_LED, (i, 1)) for i in (0, 2, 4, 6, 8, 9)),
         Request(Command.RGB_LEDS, (100, 0, 0) * 4), Request(Command.GET_SPEED)),
        (Request(Command.ALL_ACTUATORS, _PAYLOAD), Request(Command.GET_SPEED)),
    ),
}  # fmt: skip


def _batches(commands: Sequence[Command], profile: Profile) -> dict[str, Batch]:
    requests = [Request(c) for c in commands]
    plain = replace(profile, all_sensors=MappingProxyType({}))
    return {
        "e-puck1 commands": encode_batch(requests, plain),
        "all-sensors packet": encode_batch([*requests, Request(Command.ALL_SENSORS)], profile),
        "chosen": encode_batch(requests, profile),
    }


def _median_ms(link: Link, batch: Batch, rounds: int) -> float:
    times = []
    for _ in range(rounds):
        started = time.perf_counter()
        link.exchange(batch)
        times.append(time.perf_counter() - started)
    return statistics.median(times) * 1000


def measure(bluetooth: bool, rounds: int) -> list[tuple[str, str, int, float]]:
    """(set, way, bytes, median ms) for every set and way on one link."""
    rows = []
    with Epuck2Emulator("arena", seed=1, bluetooth=bluetooth) as emulator:
        assert emulator.pty_path is not None
        baud = UART_BAUD if bluetooth else DEFAULT_BAUD
        link = Link(SerialTransport(emulator.pty_path, baud))
        try:
            for name, commands in SETS.items():
                for way, batch in _batches(commands, link.profile).items():
                    size = len(batch.tx) + batch.reply_size
                    rows.append((name, way, size, _median_ms(link, batch, rounds)))
            for name, ways in ACTUATORS.items():
                for way, requests in zip(("e-puck1 commands", "-0x09"), ways, strict=True):
                    batch = encode_batch(requests, link.profile)
                    size = len(batch.tx) + batch.reply_size
                    rows.append((name, way, size, _median_ms(link, batch, rounds)))
        finally:
            link.close()
    return rows


def run(rounds: int = 30) -> str:
    """The measurements as a Markdown table."""
    lines = ["| link | enabled | e-puck1 commands | all-sensors packet | chosen |",
             "|---|---|---|---|---|"]  # fmt: skip
    for bluetooth in (False, True):
        rows = measure(bluetooth, rounds)
        for name in SETS:
            cells = {way: f"{size} B, {ms:.2f} ms" for n, way, size, ms in rows if n == name}
            chosen = next(size for n, way, size, _ in rows if n == name and way == "chosen")
            packet = next(size for n, way, size, _ in rows if n == name and "packet" in way)
            lines.append(
                f"| {'Bluetooth' if bluetooth else 'USB'} | {name} | "
                f"{cells['e-puck1 commands']} | {cells['all-sensors packet']} | "
                f"{'packet' if chosen == packet else 'e-puck1 commands'} "
                f"({cells['chosen']}) |"
            )
        lines.extend(
            f"| {'Bluetooth' if bluetooth else 'USB'} | {name} (actuators) | "
            + " | ".join(f"{size} B, {ms:.2f} ms" for n, _, size, ms in rows if n == name)
            + " (-0x09) | e-puck1 commands |"
            for name in ACTUATORS
        )
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=30, help="exchanges per cell")
    print(run(parser.parse_args().rounds))


if __name__ == "__main__":
    main()
