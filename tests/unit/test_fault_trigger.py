"""Issue 35: a fault forced for a batch number strikes that batch, whatever is in flight."""

from __future__ import annotations

from firmware_sim.faults import FaultPlan


def test_a_fault_forced_for_a_batch_waits_for_that_batch() -> None:
    plan = FaultPlan()
    plan.force("reset", batch=3)
    assert plan.for_batch(2, has_reply=False) == []  # the silent batch still on its way
    assert plan.for_batch(3, has_reply=True) == ["reset"]
    assert plan.for_batch(4, has_reply=True) == []


def test_a_fault_forced_without_a_batch_strikes_the_next_one() -> None:
    plan = FaultPlan()
    plan.force("drop")
    assert plan.for_batch(7, has_reply=True) == ["drop"]
    assert plan.for_batch(8, has_reply=True) == []


def test_a_fault_forced_for_a_batch_already_gone_is_dropped() -> None:
    plan = FaultPlan()
    plan.force("garble", batch=2)
    assert plan.for_batch(5, has_reply=True) == []
    assert plan.injected["garble"] == 0


def test_a_forced_corruption_strikes_only_its_batch() -> None:
    plan = FaultPlan(seed=1)
    plan.force("corrupt", batch=2)
    assert plan.corrupt_chunk(b"\xbb\x00", 1) == (b"\xbb\x00", False)
    data, hit = plan.corrupt_chunk(b"\xbb\x00", 2)
    assert hit and data != b"\xbb\x00"
    assert plan.corrupt_chunk(b"\xbb\x00", 2) == (b"\xbb\x00", False)  # once
