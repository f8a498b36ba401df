"""The serial link: command overhead (thesis Tables 4.1-4.2) and its rate (sections 4.1.1, 5.2).

Overhead is computed from the protocol tables (bytes on the wire per command), for both
firmware profiles. The rate is measured over the emulated 230400-baud pty link, whose
emulator paces bytes at 10 bits each (43.4 us/byte, the wire limit): the thesis measured
84.03 us/byte on the real dsPIC, and 53.5 ms for its worst-case step of 124 bytes.
"""

from __future__ import annotations

import os
import select
import statistics
import time
import tty
from dataclasses import dataclass

from benchmarks.common import (
    Stats,
    Table,
    emulator_process,
    fmt,
    progress,
    thesis_csv,
)
from ego.seam.batch import Batch
from ego.serial import Command, Firmware, Link, LinkSettings, Request, SerialTransport, encode_batch
from ego.serial.profiles import PROFILES, wire_time_s
from firmware_sim.dspic import WORK_S

__all__ = [
    "bare_client",
    "ego_client",
    "modelled_s",
    "overhead_tables",
    "run",
    "worst_case_requests",
]

_THESIS_ORDER = "a D E L M N O P Q u"
_ARGS = {Command.SET_SPEED: (0, 0), Command.SET_LED: (0, 0), Command.SET_STEPS: (0, 0)}


def _request(command: Command) -> Request:
    return Request(command, _ARGS.get(command, ()))


def worst_case_requests(firmware: Firmware = Firmware.WEBOTS) -> list[Request]:
    """Every Table 4.1 command once, LEDs for the whole ring: the thesis' worst case."""
    profile = PROFILES[firmware]
    reqs = []
    for letter in _THESIS_ORDER.split():
        command = Command((-ord(letter)) & 0xFF)
        if not profile.supports(command):
            continue
        if command is Command.SET_LED:
            reqs.extend(Request(command, (i, 0)) for i in range(8))
        else:
            reqs.append(_request(command))
    return reqs


def overhead_tables() -> list[Table]:
    thesis_pct = {
        "a": 14.3,
        "D": 20.0,
        "E": 20.0,
        "L": 33.3,
        "M": 14.3,
        "N": 5.9,
        "O": 5.9,
        "P": 20.0,
        "Q": 20.0,
        "u": 14.3,
    }
    tables = []
    for firmware, profile in PROFILES.items():  # the firmwares a serial line speaks
        table = Table(
            key=f"command_overhead_{firmware.value}",
            title=f"Command overhead, {firmware.value} firmware (thesis Tables 4.1, 4.2)",
            columns=[
                "command",
                "sent bytes",
                "reply bytes",
                "useful",
                "overhead",
                "overhead %",
                "thesis %",
            ],
        )
        for letter in _THESIS_ORDER.split():
            command = Command((-ord(letter)) & 0xFF)
            if not profile.supports(command):
                table.rows.append(
                    [letter, "-", "-", "-", "-", "not served", fmt(thesis_pct[letter], 1)]
                )
                continue
            fmt_ = profile.wire_format(command)
            useful = fmt_.arguments.size + fmt_.reply.size + fmt_.prefix.size
            table.rows.append(
                [
                    letter,
                    1 + fmt_.arguments.size,
                    fmt_.reply.size,
                    useful,
                    1,
                    100.0 / (1 + useful),
                    thesis_pct[letter],
                ]
            )
        batch = encode_batch(worst_case_requests(firmware), profile)
        sent_useful = sum(profile.wire_format(r.command).arguments.size for r in batch.requests)
        overhead = len(batch.requests) + 1
        useful = sent_useful + batch.reply_size
        table.notes.append(
            f"All commands in one step ({len(batch.requests)} commands, LEDs for the ring): "
            f"{len(batch.tx)} bytes sent + {batch.reply_size} received = "
            f"{len(batch.tx) + batch.reply_size} bytes; overhead {overhead} bytes = "
            f"{100 * overhead / (overhead + useful):.1f} % (thesis: 124 bytes, 19 command bytes, "
            "15.3 %)."
        )
        tables.append(table)
    return tables


@dataclass(frozen=True)
class LinkRun:
    """One client's steps: wall times (s) and CPU seconds per step."""

    times: list[float]
    cpu_s: float


def ego_client(
    path: str, batch: Batch, steps: int, label: str, settings: LinkSettings | None = None
) -> LinkRun:
    """ego's Link doing ``steps`` exchanges of ``batch``."""
    link = Link(SerialTransport(path), firmware="webots", settings=settings or LinkSettings())
    try:
        times = []
        cpu0 = time.process_time()
        for _ in progress(range(steps), label, total=steps):
            t0 = time.perf_counter()
            link.exchange(batch)
            times.append(time.perf_counter() - t0)
        cpu = time.process_time() - cpu0
    finally:
        link.close()
    return LinkRun(times, cpu / steps)


def bare_client(path: str, tx: bytes, reply_size: int, steps: int, label: str) -> LinkRun:
    """The least a Python client can do: os.write the batch, os.read the reply's bytes."""
    fd = os.open(path, os.O_RDWR | os.O_NOCTTY | os.O_NONBLOCK)
    try:
        tty.setraw(fd)
        while select.select([fd], [], [], 0.1)[0]:  # the power-on banner, if still there
            os.read(fd, 4096)
        times = []
        cpu0 = time.process_time()
        for _ in progress(range(steps), label, total=steps):
            t0 = time.perf_counter()
            view = memoryview(tx)
            while view:
                view = view[os.write(fd, view) :]
            got = 0
            while got < reply_size:
                if not select.select([fd], [], [], 2.0)[0]:
                    raise TimeoutError(f"the bare client got {got} of {reply_size} bytes")
                got += len(os.read(fd, 4096))
            times.append(time.perf_counter() - t0)
        cpu = time.process_time() - cpu0
    finally:
        os.close(fd)
    return LinkRun(times, cpu / steps)


@dataclass(frozen=True)
class Setting:
    """One emulator set-up: its flags and the time it models per step (s)."""

    label: str
    flags: tuple[str, ...]
    delay_us: float
    work: bool


SETTINGS = (
    Setting("thesis-comparable: dsPIC work modelled, 0 us/command", (), 0.0, True),
    Setting(
        "thesis-comparable: dsPIC work modelled, 40 us/command",
        ("--processing-delay-us", "40"),
        40.0,
        True,
    ),
    Setting("no modelled dsPIC time: the wire only", ("--no-dspic-work",), 0.0, False),
)


def modelled_s(batch: Batch, setting: Setting) -> float:
    """What the emulator spends on one step by design: both ways' wire time, the
    per-command delay and the firmware's modelled work (firmware_sim.dspic.WORK_S)."""
    letters = [chr((-int(r.command)) & 0xFF) for r in batch.requests]
    work = sum(WORK_S.get(c, 0.0) for c in letters) if setting.work else 0.0
    wire = wire_time_s(len(batch.tx) + batch.reply_size)
    return wire + setting.delay_us * 1e-6 * (len(batch.requests) + 1) + work


def run(quick: bool = False) -> list[Table]:
    tables = overhead_tables()
    steps, rounds = (30, 1) if quick else (2000, 3)
    batch = encode_batch(worst_case_requests(), PROFILES[Firmware.WEBOTS])
    per_step = len(batch.tx) + batch.reply_size
    results: dict[tuple[str, str], list[LinkRun]] = {}
    for setting in SETTINGS:
        with emulator_process(*setting.flags) as path:
            # Rounds of ego then the bare client on the same pty: a slow moment hits both.
            for i in range(rounds):
                results.setdefault((setting.label, "ego"), []).append(
                    ego_client(path, batch, steps, f"link ego {i + 1}/{rounds}")
                )
                results.setdefault((setting.label, "ego-noguard"), []).append(
                    ego_client(
                        path,
                        batch,
                        steps,
                        f"link ego, no guard {i + 1}/{rounds}",
                        LinkSettings(trailing_guard_s=0.0),
                    )
                )
                results.setdefault((setting.label, "bare"), []).append(
                    bare_client(
                        path, batch.tx, batch.reply_size, steps, f"link bare {i + 1}/{rounds}"
                    )
                )
    tables.append(_rate_table(results, batch, per_step, steps * rounds))
    return tables


CLIENT_LABELS = {
    "ego": "ego Link",
    "ego-noguard": "ego Link, trailing guard off",
    "bare": "bare os.write/os.read",
}


def _rate_table(
    results: dict[tuple[str, str], list[LinkRun]], batch: Batch, per_step: int, steps: int
) -> Table:
    thesis = {row["figure"]: row for row in thesis_csv("serial_link.csv")}
    thesis_us = (
        float(thesis["effective_time_per_byte"]["value"])
        if ("effective_time_per_byte" in thesis)
        else 84.03
    )
    table = Table(
        key="serial_link_rate",
        title=f"Serial link rate over the emulated 230400-baud pty, worst-case step of "
        f"{per_step} bytes, {steps} steps per row (thesis sections 4.1.1, 5.2)",
        columns=[
            "emulator",
            "client",
            "median step [ms]",
            "min",
            "max",
            "us/byte",
            "modelled us/byte",
            "own us/byte",
            "CPU us/step",
            "x wire",
            "thesis us/byte",
        ],
    )
    for setting in SETTINGS:
        model = modelled_s(batch, setting)
        wire = wire_time_s(per_step)
        for client in ("ego", "ego-noguard", "bare"):
            runs = results[(setting.label, client)]
            times = [t for r in runs for t in r.times]
            stats = Stats.of(times)
            mean = sum(times) / len(times)
            table.rows.append(
                [
                    setting.label,
                    CLIENT_LABELS[client],
                    stats.median * 1e3,
                    stats.low * 1e3,
                    stats.high * 1e3,
                    mean / per_step * 1e6,
                    model / per_step * 1e6,
                    (stats.median - model) / per_step * 1e6,
                    statistics.median(r.cpu_s for r in runs) * 1e6,
                    "-" if setting.work else stats.median / wire,
                    thesis_us if setting.work and not setting.delay_us else "-",
                ]
            )
    table.notes.append(
        "us/byte is the mean step over the bytes of a step (sent and received), the thesis' "
        "measure; the thesis-comparable rows include what the emulator models on purpose: "
        "the wire (43.4 us/byte at 230400 baud), M's 3 ms I2C read of the floor sensors "
        "(firmware_sim.dspic.WORK_S) and, in the second, 40 us per command. 'own us/byte' "
        "is the median step less that modelled time, over the bytes: what the client adds "
        "(the median, as a loaded machine's stalls land in the mean). The bare client is "
        "the least "
        "a Python program can do on the same pty (os.write the batch, select and os.read "
        "until the reply's bytes are in); ego's own cost is best read against it. CPU "
        "us/step is the client process's time.process_time per step (the emulator runs in "
        "its own process). 'x wire' (rows without modelled dsPIC time) is the median step "
        "over the wire time of its bytes. ego's default Link watches 6 byte times after "
        "each reply for a byte that should not be there (LinkSettings.trailing_guard_s); "
        "'trailing guard off' shows what that watch costs."
    )
    return table
