"""Soak under faults: thousands of steps per fault kind, every delivered value checked.

A robot samples every sensor at every step against the emulator, which injects one kind
of fault (or all kinds mixed) at a rate per batch. After each step the values the robot
delivers are compared with the emulator's ground truth: the clean reply of the batch it
answered last, decoded here independently of the library's tables. Reported per run:
faults injected, steps that hit a fault and recovered, steps that surfaced a typed error,
wrong values delivered (the target is zero), garbled replies that slipped through (a
flipped bit inside a reply of the right length, which this protocol cannot see; the
plausibility guard catches those that leave a value's range), and the longest time a
step blocked beside the bound the link's settings allow.
"""

from __future__ import annotations

import logging
import random
import struct
import time
from dataclasses import dataclass, field
from datetime import datetime, timezone
from pathlib import Path

import ego
from benchmarks.common import THESIS_LINE_BAUD, Table, print_and_save, progress
from ego.devices.encoders import wrap_int16
from ego.errors import EgoError
from ego.serial import Batch, Command, Link, LinkSettings, Request, SerialTransport, encode_batch
from ego.serial.transport import MIN_BAUD
from firmware_sim import FAULT_KINDS, Emulator, FaultSpec, FaultTimings

__all__ = ["SoakResult", "run", "soak", "step_bound_s"]

#: The emulator's reply formats, written from protocol.md (not the library's tables).
_TRUTH_FORMATS = {
    "a": struct.Struct("<3H"),
    "E": struct.Struct("<2h"),
    "M": struct.Struct("<3H"),
    "N": struct.Struct("<8h"),
    "O": struct.Struct("<8h"),
    "Q": struct.Struct("<2h"),
    "u": struct.Struct("<3H"),
}

#: Soak settings: the defaults but a shorter quiet time, so that 10,000 steps x 5 % of
#: resynchronisations finish in minutes; fault lengths to match.
SOAK_LINK = LinkSettings(resync_quiet_s=0.03, reconnect_timeout_s=2.0)
SOAK_FAULTS = FaultTimings(delay_s=0.08, stall_s=0.4, replug_s=0.2)
#: How many wrong values a run describes in the report.
MAX_WRONG_EXAMPLES = 5


@dataclass
class SoakResult:
    label: str
    rate: float
    steps: int = 0
    injected: int = 0
    injected_by_kind: dict[str, int] = field(default_factory=dict)
    recovered_steps: int = 0
    typed_errors: int = 0
    error_types: dict[str, int] = field(default_factory=dict)
    wrong_values: int = 0
    #: Steps after which the dsPIC held other speeds, or other LEDs, than ego commanded.
    speeds_off: int = 0
    leds_off: int = 0
    garbles_delivered: int = 0
    guard_rejections: int = 0
    longest_step_s: float = 0.0
    bound_s: float = 0.0
    wall_s: float = 0.0
    #: The step at which the link was lost for good (``Robot.step`` returned -1), if it was.
    lost_at_step: int | None = None
    #: The first few wrong values, to say what went wrong: (step, letter, delivered,
    #: truth, the faults of the batch answered).
    wrong_examples: list[tuple[int, str, object, object, str]] = field(default_factory=list)


def step_bound_s(settings: LinkSettings, reply_timeout_s: float, restarts: int = 3) -> float:
    """The longest a step may block: every retry times out, every restart re-probes."""
    guard_s = settings.trailing_guard_at(MIN_BAUD)  # its longest: on the slowest line
    attempt = reply_timeout_s + guard_s + settings.resync_max_s
    identify = settings.resync_max_s + 3 * settings.line_timeout_s
    per_exchange = (settings.retries + 1) * attempt + settings.reconnect_timeout_s + identify
    return restarts * per_exchange


def _truth(letters: str, reply: bytes) -> dict[str, tuple[int, ...]] | None:
    values: dict[str, tuple[int, ...]] = {}
    offset = 0
    for letter in letters:
        fmt = _TRUTH_FORMATS.get(letter)
        if fmt is None:
            continue
        if offset + fmt.size > len(reply):
            return None
        values[letter] = tuple(int(v) for v in fmt.unpack_from(reply, offset))
        offset += fmt.size
    return values


def _delivered(robot: ego.Robot) -> dict[str, tuple[int, ...]]:
    return {
        "a": robot.accelerometer.values,
        "E": robot.motors.values,
        "M": robot.floor.values,
        "N": robot.proximity.values,
        "O": robot.light.values,
        "Q": tuple(wrap_int16(v) for v in robot.encoders.values),
        "u": robot.microphones.values,
    }


def soak(kinds: list[str], rate: float, steps: int, seed: int = 1, label: str = "") -> SoakResult:
    """Run ``steps`` steps with ``kinds`` injected at ``rate`` per batch; check every value."""
    logger = logging.getLogger("ego")
    level = logger.level
    logger.setLevel(logging.CRITICAL)  # faults are counted, not logged
    try:
        return _soak(kinds, rate, steps, seed, label)
    finally:
        logger.setLevel(level)  # the process's logging as it was (a test suite goes on)


def _soak(kinds: list[str], rate: float, steps: int, seed: int, label: str) -> SoakResult:
    result = SoakResult(label or "+".join(kinds), rate)
    rng = random.Random(seed)
    faults = [FaultSpec(kind, rate=rate) for kind in kinds]
    with Emulator(
        "webots", baud=THESIS_LINE_BAUD, seed=seed, faults=faults, timings=SOAK_FAULTS
    ) as emu:
        robot = ego.Robot(channel=Link(SerialTransport(emu.path), settings=SOAK_LINK))
        try:
            for family in (
                robot.accelerometer,
                robot.motors,
                robot.floor,
                robot.proximity,
                robot.light,
                robot.encoders,
                robot.microphones,
            ):
                family.enable(1)
            started = time.perf_counter()
            for i in progress(range(steps), result.label, total=steps):
                if i % 50 == 0:
                    robot.motors.set_speed(rng.randint(-800, 800), rng.randint(-800, 800))
                    robot.leds.set(rng.randrange(8), 2)
                stats = robot.channel.stats
                before = (stats.retries, stats.restarts, stats.faults["implausible"])
                t0 = time.perf_counter()
                try:
                    if robot.step(1) != 0:
                        result.lost_at_step = i
                        break
                except EgoError as exc:
                    result.typed_errors += 1
                    name = type(exc).__name__
                    result.error_types[name] = result.error_types.get(name, 0) + 1
                    continue
                finally:
                    result.longest_step_s = max(result.longest_step_s, time.perf_counter() - t0)
                    result.steps += 1
                if (stats.retries, stats.restarts, stats.faults["implausible"]) != before:
                    result.recovered_steps += 1
                world = emu.world
                result.speeds_off += world.speeds != robot.motors.speed
                result.leds_off += world.leds != robot.leds.values
                record = emu.history[-1]
                truth = _truth(record.commands, record.reply) or {}
                delivered = _delivered(robot)
                wrong = [k for k, v in delivered.items() if truth.get(k) != v]
                if not wrong:
                    continue
                if "garble" in record.faults:
                    result.garbles_delivered += 1
                    continue
                result.wrong_values += 1
                if len(result.wrong_examples) < MAX_WRONG_EXAMPLES:
                    letter = wrong[0]
                    faults = ",".join(record.faults) or "none"
                    example = (i, letter, delivered[letter], truth.get(letter), faults)
                    result.wrong_examples.append(example)
            result.wall_s = time.perf_counter() - started
        finally:
            robot.close()
        result.injected_by_kind = dict(emu.plan.injected)
        result.injected = sum(emu.plan.injected.values())
        result.guard_rejections = robot.channel.stats.faults.get("implausible", 0)
    batch_timeout = robot.channel.timeout_for(_full_batch(robot))
    result.bound_s = step_bound_s(SOAK_LINK, batch_timeout)
    return result


def _full_batch(robot: ego.Robot) -> Batch:
    letters = [
        Command.ACCELEROMETER_RAW,
        Command.GET_SPEED,
        Command.FLOOR,
        Command.PROXIMITY,
        Command.LIGHT,
        Command.GET_STEPS,
        Command.MIC_AMPLITUDE,
    ]
    return encode_batch([Request(c) for c in letters], robot.channel.profile)


def run(quick: bool = False) -> list[Table]:
    steps = 300 if quick else 10_000
    kinds = [k for k in FAULT_KINDS]
    plan = [([k], r) for r in (0.01, 0.05) for k in kinds] + [(kinds, 0.01), (kinds, 0.05)]
    if quick:
        plan = [([k], 0.05) for k in kinds] + [(kinds, 0.01)]
    table = Table(
        key="reliability_soak",
        title=f"Soak under faults: {steps} steps per run, every sensor every step, "
        "values checked against the emulator's ground truth",
        columns=[
            "faults",
            "rate",
            "steps",
            "injected",
            "steps recovered",
            "typed errors",
            "wrong values",
            "garbles delivered",
            "speeds off",
            "LEDs off",
            "link lost",
            "longest step [ms]",
            "bound [ms]",
            "wall [s]",
        ],
    )
    for kinds_, rate in plan:
        label = "all mixed" if len(kinds_) > 1 else kinds_[0]
        r = soak(kinds_, rate, steps, label=label)
        errors = ", ".join(f"{k} {v}" for k, v in sorted(r.error_types.items())) or "-"
        for step, letter, got, truth, faults in r.wrong_examples:
            table.notes.append(
                f"{label} at {rate:.0%}, step {step}: {letter} delivered {got}, the emulator "
                f"answered {truth} (faults in that batch: {faults})"
            )
        table.rows.append(
            [
                label,
                f"{rate:.0%}",
                r.steps,
                r.injected,
                r.recovered_steps,
                f"{r.typed_errors} ({errors})",
                r.wrong_values,
                r.garbles_delivered,
                r.speeds_off,
                r.leds_off,
                "-" if r.lost_at_step is None else f"at step {r.lost_at_step}",
                r.longest_step_s * 1e3,
                r.bound_s * 1e3,
                r.wall_s,
            ]
        )
    table.notes.append(
        "garble flips one bit inside a reply of the right length: no length check can see "
        "it, so it is counted apart from wrong values; out-of-range values are caught by the "
        "plausibility guard. 'bound' is the longest a step may block under the link's settings "
        "(every retry timing out, three restarts)."
    )
    return [table]


def write_markdown(tables: list[Table], path: Path, machine: str, quick: bool) -> None:
    """benchmarks/results/reliability.md: the soak's figures and what they mean."""
    lines = [
        "# Reliability: soak under faults",
        "",
        f"- date: {datetime.now(timezone.utc):%Y-%m-%d %H:%M} UTC; machine: {machine}",
        f"- mode: {'quick' if quick else 'full'}; link settings: resync quiet "
        f"{SOAK_LINK.resync_quiet_s * 1e3:.0f} ms, otherwise the defaults; fault lengths: delay "
        f"{SOAK_FAULTS.delay_s * 1e3:.0f} ms, stall {SOAK_FAULTS.stall_s * 1e3:.0f} ms, "
        f"unplugged {SOAK_FAULTS.replug_s * 1e3:.0f} ms",
        "- each step asks every sensor (a E M N O Q u, 58 reply bytes) and, every 50 steps, "
        "new speeds and an LED toggle; the delivered values are compared with the clean reply "
        "the emulator recorded for the batch it answered",
        "",
    ]
    for table in tables:
        lines.append(table.markdown())
    lines += [
        "## What the columns mean",
        "",
        "- **injected**: faults the emulator applied. **steps recovered**: steps that met a "
        "fault (a retry, a restart, or an implausible reply asked again) and still delivered. "
        "**typed errors**: steps that raised an `ego.errors` error after the bounded retries "
        "(a stall longer than the retries cover surfaces as `LinkTimeoutError`).",
        "- **wrong values**: values delivered that differ from the emulator's ground truth "
        "for any reason other than a garble: the target is zero.",
        "- **garbles delivered**: a flipped bit inside a reply of the right length. The "
        "protocol has no checksum, so nothing can see such a flip; ego's plausibility guard "
        "catches the flips that take a value out of its range (the top 4 bits of a 12-bit "
        "sensor value, any flip in `E`, which must echo the commanded speeds, and step "
        "counters that jump further than the wheels can turn), and asks again. What stays in "
        "range is delivered: this is the protocol's limit, measured here, not hidden.",
        "- **speeds off**, **LEDs off**: steps after which the dsPIC held other wheel speeds, "
        "or other LEDs, than ego had commanded. A corrupted byte on the way in can make the "
        "dsPIC misread a command. ego catches it wherever it can read back what it changed: "
        "every `D` travels with an `E` that must echo the speeds (else `D` goes again), and "
        "step counters that jump twice alike (a byte misread as `P`) are set back to the "
        "last good reading. `L` has no read-back on this protocol: an LED command the dsPIC "
        "misread stays wrong until that LED is set again, counted here.",
        "- **link lost**: the step at which the link was lost for good (`Robot.step` "
        "returned -1: a port not back within the reconnect timeout); the run stops there.",
        "- **longest step** is bounded by the link's settings: every retry timing out and "
        "three restarts (the `bound` column).",
        "",
        "## Recovery",
        "",
        "After a dsPIC reset (its banner mid-stream) or an unplugged and re-plugged port, the "
        "link resynchronises, re-detects the firmware with `V`, and raises `RobotResetError` "
        "inside `Robot.step`, which re-applies the motors' speeds, the LEDs that were on and "
        "the step counters (`P` with the last totals) and asks again; each event is logged "
        "at WARNING.",
    ]
    path.parent.mkdir(parents=True, exist_ok=True)
    # The security section is benchmarks/security.py's: kept as it is.
    old = path.read_text() if path.exists() else ""
    begin, end = "<!-- security:begin -->", "<!-- security:end -->"
    kept = old[old.index(begin) : old.index(end) + len(end)] if begin in old else ""
    path.write_text("\n".join(lines) + "\n" + ("\n" + kept + "\n" if kept else ""))


def main(argv: list[str] | None = None) -> int:
    import argparse

    from benchmarks.__main__ import machine_description

    parser = argparse.ArgumentParser(prog="python -m benchmarks.reliability")
    parser.add_argument("--quick", action="store_true", help="300 steps per run, fewer runs")
    args = parser.parse_args(argv)
    tables = run(quick=args.quick)
    folder = print_and_save(tables, args.quick)
    write_markdown(tables, folder / "reliability.md", machine_description(), args.quick)
    print(f"\nreport: {folder / 'reliability.md'}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
