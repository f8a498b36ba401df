"""The serial link: command overhead (thesis Tables 4.1-4.2) and its rate (sections 4.1.1, 5.2).

Overhead is computed from the protocol tables (bytes on the wire per command), for both
firmware profiles. The rate is measured over the emulated 230400-baud pty link, whose
emulator paces bytes at 10 bits each (43.4 us/byte, the wire limit): the thesis measured
84.03 us/byte on the real dsPIC, and 53.5 ms for its worst-case step of 124 bytes.
"""

from __future__ import annotations

import time

from benchmarks.common import THESIS_LINE_BAUD, Stats, Table, fmt, progress, thesis_csv
from ego.serial import Command, Firmware, Link, Request, SerialTransport, encode_batch
from ego.serial.protocol import PROFILES, wire_time_s
from firmware_sim import Emulator

__all__ = ["overhead_tables", "run", "worst_case_requests"]

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
    for firmware in Firmware:
        profile = PROFILES[firmware]
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


def _link_rate(steps: int, processing_delay_us: float) -> tuple[Stats, float, int]:
    """Per-step round trips (s), us per byte, and bytes a step, over the emulated link."""
    with Emulator(
        "webots", baud=THESIS_LINE_BAUD, seed=1, processing_delay_s=processing_delay_us * 1e-6
    ) as emu:
        link = Link(SerialTransport(emu.path), firmware="webots")
        try:
            batch = encode_batch(worst_case_requests(), link.profile)
            per_step = len(batch.tx) + batch.reply_size
            times = []
            for _ in progress(range(steps), f"link {processing_delay_us:g} us/cmd", total=steps):
                t0 = time.perf_counter()
                link.exchange(batch)
                times.append(time.perf_counter() - t0)
        finally:
            link.close()
    return Stats.of(times), sum(times) / (steps * per_step) * 1e6, per_step


def run(quick: bool = False) -> list[Table]:
    tables = overhead_tables()
    steps = 300 if quick else 10_000
    thesis = {row["figure"]: row for row in thesis_csv("serial_link.csv")}
    thesis_us = (
        float(thesis["effective_time_per_byte"]["value"])
        if ("effective_time_per_byte" in thesis)
        else 84.03
    )
    wire_us = wire_time_s(1) * 1e6
    table = Table(
        key="serial_link_rate",
        title=f"Serial link rate over the emulated 230400-baud pty, worst-case step, {steps} steps "
        "(thesis sections 4.1.1, 5.2)",
        columns=[
            "emulator dsPIC delay",
            "bytes/step",
            "median step [ms]",
            "min",
            "max",
            "us/byte",
            "ratio to wire 43.4 us/byte",
            "thesis us/byte",
            "thesis worst step [ms]",
        ],
    )
    for delay in (0.0, 40.0):
        stats, us_per_byte, per_step = _link_rate(steps, delay)
        table.rows.append(
            [
                f"{delay:g} us/command",
                per_step,
                stats.median * 1e3,
                stats.low * 1e3,
                stats.high * 1e3,
                us_per_byte,
                us_per_byte / wire_us,
                thesis_us,
                53.5,
            ]
        )
    table.notes.append(
        "With no dsPIC delay the emulator answers at the wire's pace, so us/byte shows ego's own "
        "cost on top of the wire; 40 us per command models a dsPIC's parsing time."
    )
    tables.append(table)
    return tables
