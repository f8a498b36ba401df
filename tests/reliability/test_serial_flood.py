"""Issue 32, item 6: a peer on a serial line that never stops sending. The drain that
resynchronises a line was bounded by time only: each step took 7-8.5 s (every retry
drained for a second, twice) before a typed error, close 8.2 s, and memory grew to
62-103 MB. Now a drain stops at ``resync_max_bytes`` or ``resync_max_s``, whichever comes
first; a line still sending then is flooded, and the step fails at once with
LineFloodedError (an ExtraBytesError), no retry: within the batch's reply timeout plus
``resync_max_s``, and the 0.5 s of scheduling docs/bad_input.md allows. Close as fast.

A real pty stands between ego and the emulated e-puck2's own pty (``pty_flood``): it
relays every byte until told to flood, at a UART's rate or as fast as the pty goes."""

from __future__ import annotations

import logging
import time
import tracemalloc
from collections.abc import Iterator

import pytest
from pty_flood import FloodingRelay

import ego
from ego.errors import ExtraBytesError, LineFloodedError
from ego.serial.link import LinkSettings
from firmware_sim.epuck2 import Epuck2Emulator

SETTINGS = LinkSettings()
#: docs/bad_input.md: a flooded step fails within the reply timeout (tens of ms here) plus
#: resync_max_s, plus 0.5 s of scheduling on a loaded machine.
STEP_BOUND_S = SETTINGS.resync_max_s + 0.5
#: What a flooded step may allocate: a few drains' worth of bytes, never the flood.
MEMORY_BOUND = 4 * 65536 + (1 << 18)  # 4 x LinkSettings.resync_max_bytes, and some


@pytest.fixture(params=[None, 11520], ids=["pty-speed", "115200-baud"])
def relay(request: pytest.FixtureRequest) -> Iterator[FloodingRelay]:
    with Epuck2Emulator("arena", seed=3) as emulator:
        assert emulator.pty_path is not None
        with FloodingRelay(emulator.pty_path, request.param) as relay:
            yield relay


def test_a_flooded_line_fails_each_step_in_bounded_time_and_memory(
    relay: FloodingRelay, caplog: pytest.LogCaptureFixture
) -> None:
    robot = ego.Robot(relay.path)
    try:
        robot.proximity.enable(32)
        robot.step(32)
        relay.flood()
        for _ in range(2):
            tracemalloc.start()
            start = time.monotonic()
            with pytest.raises(LineFloodedError, match="never went quiet") as caught:
                robot.step(32)
            took = time.monotonic() - start
            _, peak = tracemalloc.get_traced_memory()
            tracemalloc.stop()
            assert isinstance(caught.value, ExtraBytesError)
            assert took < STEP_BOUND_S, f"a flooded step took {took:.2f} s"
            assert peak < MEMORY_BOUND, f"a flooded step held {peak / 1e6:.1f} MB"
    finally:
        start = time.monotonic()
        with caplog.at_level(logging.ERROR, logger="ego"):
            robot.close()
        took = time.monotonic() - start
    assert took < STEP_BOUND_S, f"close took {took:.2f} s"
    assert robot.closed
    # The stop could not be confirmed, and ego says so rather than pretending.
    assert any("could not stop" in r.getMessage() for r in caplog.records)
    assert relay.flooded > 0
