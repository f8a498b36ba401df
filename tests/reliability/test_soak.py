"""A short soak under every fault kind: no wrong value is ever delivered, no step blocks unbounded.

The full soak (10,000 steps per kind at 1 % and 5 %) is ``python -m benchmarks --only
reliability``; this is its short version, run by the test suite.
"""

from __future__ import annotations

import pytest

from benchmarks.reliability import soak
from firmware_sim import FAULT_KINDS

STEPS = 150


@pytest.mark.slow
@pytest.mark.parametrize("kind", FAULT_KINDS)
def test_soak_never_delivers_a_wrong_value(kind: str) -> None:
    result = soak([kind], rate=0.05, steps=STEPS, seed=3)
    assert result.injected > 0, "the soak injected nothing: it tested nothing"
    assert result.lost_at_step is None
    assert result.wrong_values == 0
    assert result.speeds_off == 0  # every D is confirmed by the E behind it
    assert result.longest_step_s <= result.bound_s
    if kind != "garble":
        assert result.garbles_delivered == 0
    if kind != "corrupt":  # only a misread L command, which nothing reads back, leaves one off
        assert result.leds_off == 0


@pytest.mark.slow
def test_soak_with_every_kind_mixed_never_delivers_a_wrong_value() -> None:
    result = soak(list(FAULT_KINDS), rate=0.01, steps=2 * STEPS, seed=4)
    assert result.lost_at_step is None
    assert result.wrong_values == 0
    assert result.speeds_off == 0
    assert result.longest_step_s <= result.bound_s
    assert result.steps == 2 * STEPS


def test_the_guard_rejects_garbled_replies_that_leave_their_range() -> None:
    result = soak(["garble"], rate=0.2, steps=100, seed=5)
    # A flip in the top four bits of a 12-bit value, or anywhere in E (checked against the
    # commanded speeds), is caught; a flip inside the range is not, and is counted.
    assert result.guard_rejections > 0
    assert result.wrong_values == 0
