"""The sim backend's emulator answers from threads of the controller's own process: a busy
host may hold its replies up, which a real dsPIC never does. Its link allows for that
(firmware_sim.ego_backend.IN_PROCESS_SLACK_S) and still notices an emulator that stopped
answering; a real port keeps the dsPIC's strict timeout (docs/protocol.md, Timing)."""

from __future__ import annotations

import pytest
from helpers import emulator_of

import ego
from ego.errors import OutOfRangeError
from ego.serial.transport import SerialTransport
from firmware_sim.ego_backend import IN_PROCESS_SLACK_S
from firmware_sim.faults import FaultTimings, parse_fault

#: Longer than a real dsPIC's reply timeout for a step's batch (25 ms of slack plus
#: three times the wire), well inside the in-process slack: what a starved emulator
#: thread looked like on a busy 2-core machine (30 ms late, four replies in a row).
HELD_UP_S = 0.06
STEP_MS = 32


def test_replies_held_up_by_the_host_are_not_taken_for_a_dead_line() -> None:
    late = parse_fault("delay@4,5,6,7")
    with ego.Robot("sim", seed=1, faults=[late], timings=FaultTimings(delay_s=HELD_UP_S)) as robot:
        robot.proximity.enable(STEP_MS)
        for _ in range(10):
            robot.step(STEP_MS)
        delayed = [r for r in emulator_of(robot).history if "delay" in r.faults]
        assert len(delayed) == 4  # four late replies in a row, and the controller lives
        assert len(robot.proximity.values) == 8


def test_an_emulator_that_stops_answering_is_still_noticed() -> None:
    # A stall far past the slack: the link times out, resynchronises and steps on.
    stall = parse_fault("stall@4")
    timings = FaultTimings(stall_s=4 * IN_PROCESS_SLACK_S)
    with ego.Robot("sim", seed=1, faults=[stall], timings=timings) as robot:
        robot.proximity.enable(STEP_MS)
        for _ in range(8):
            robot.step(STEP_MS)
        assert robot.channel.stats.faults["LinkTimeoutError"] >= 1


def test_a_modelled_radio_latency_is_waited_for_both_ways() -> None:
    # Robot("sim", latency_s=...) models a Bluetooth link's delay each way: a round trip
    # is twice that (0.2 s, beyond a real dsPIC's 25 ms), and the link waits for it.
    with ego.Robot("sim", seed=1, latency_s=0.1) as robot:
        robot.proximity.enable(STEP_MS)
        for _ in range(5):
            robot.step(STEP_MS)
        assert len(robot.proximity.values) == 8


@pytest.mark.parametrize("latency_s", [-0.001, float("nan"), 61.0])
def test_a_transport_latency_out_of_range_is_refused(latency_s: float) -> None:
    with pytest.raises(OutOfRangeError, match="reply latency"):
        SerialTransport("loop://", latency_s=latency_s)
