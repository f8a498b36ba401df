"""What the emulated Pi-puck's robot was told and did: one frozen snapshot for tests."""

from __future__ import annotations

from dataclasses import dataclass

from firmware_sim.epuck2.motors import int16
from firmware_sim.pipuck.gumstix import GumstixMcu
from firmware_sim.pipuck.machine import PipuckMachine
from firmware_sim.pipuck.york import YorkEpuck1

__all__ = ["PipuckTruth", "truth_of"]


@dataclass(frozen=True, slots=True)
class PipuckTruth:
    """Ground truth.

    ``speeds``: what the motors run at, after the firmware's clamp (steps/s).
    ``steps``: the step counters as the firmware sends them (e-puck2 int16, e-puck1
    uint16). ``red_leds``: the e-puck2's LED1, 3, 5, 7 or the e-puck1's ring LED0..7.
    ``rgb_leds``: the e-puck2's LED2, 4, 6, 8 as (r, g, b) bytes (the firmware means
    0..100); empty on the e-puck1. ``sounds``: melodies asked for, one per packet that
    asked. ``packets``: actuator packets (e-puck2) or register writes (e-puck1) received;
    ``checksum_errors``: packets dropped for a wrong XOR. ``last_packet``: the last
    20-byte packet (e-puck2). ``last_was_stop``: the last packet was a valid stop (speeds
    0, every LED off, no sound), or on the e-puck1 the speed and LED registers are 0.
    ``transactions``: I2C transactions on the robot's bus; ``wire_s``: the time they
    took on the wire at the bus's clock (start, address and acknowledge, nine bits a
    byte, stop).
    """

    robot: str
    speeds: tuple[int, int]
    steps: tuple[int, int]
    red_leds: tuple[bool, ...]
    rgb_leds: tuple[tuple[int, int, int], ...]
    body_led: bool
    front_led: bool
    sounds: tuple[str, ...]
    packets: int
    checksum_errors: int
    last_packet: bytes | None
    last_was_stop: bool
    ir_enabled: bool
    transactions: int
    wire_s: float


def truth_of(machine: PipuckMachine) -> PipuckTruth:
    """The snapshot now (the caller holds the machine's lock)."""
    world = machine.world
    bus = machine.buses[machine.robot_bus]
    transactions, wire_s = bus.transactions, bus.wire_s
    mcu = machine.mcu
    if isinstance(mcu, GumstixMcu):
        record, leds = mcu.record, mcu.robot.leds
        left, right = mcu.robot.steps()
        return PipuckTruth(
            "epuck2", world.speeds, (int16(left), int16(right)), tuple(leds.red),
            tuple((r, g, b) for r, g, b in leds.rgb), leds.body, leds.front,
            tuple(record.sounds), record.packets, record.checksum_errors,
            record.raw[-1] if record.raw else None,
            record.last is not None and record.last.is_stop,
            True, transactions, wire_s,
        )  # fmt: skip
    assert isinstance(mcu, YorkEpuck1)
    mcu.main_loop()
    lit = world.leds
    stopped = mcu.speeds == (0, 0) and mcu.regs[0] == 0 and mcu.regs[1] == 0
    return PipuckTruth(
        "epuck", world.speeds, (mcu.regs[4], mcu.regs[5]),
        tuple(bool(v) for v in lit[:8]), (), bool(lit[8]), bool(lit[9]), (),
        mcu.write_count, 0, None, stopped, mcu.ir_enabled, transactions, wire_s,
    )  # fmt: skip
