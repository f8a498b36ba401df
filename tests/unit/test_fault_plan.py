"""The emulator's fault model (firmware_sim.faults) on bytes alone."""

from __future__ import annotations

import pytest

from firmware_sim import FAULT_KINDS, FaultSpec, parse_fault
from firmware_sim.faults import FaultPlan


def test_every_kind_the_spec_names_exists() -> None:
    """protocol.md: "dropped, corrupted, delayed and extra bytes, a stalled line, a
    disconnect, a reset with its banner" (and garble, the undetectable one)."""
    assert set(FAULT_KINDS) == {
        "drop", "corrupt", "garble", "delay", "extra", "stall", "disconnect", "reset"
    }  # fmt: skip


@pytest.mark.parametrize(
    ("text", "spec"),
    [
        ("drop=0.01", FaultSpec("drop", rate=0.01)),
        (" reset =1", FaultSpec("reset", rate=1.0)),
        ("reset@500", FaultSpec("reset", at_batches=frozenset({500}))),
        ("stall@3,7", FaultSpec("stall", at_batches=frozenset({3, 7}))),
    ],
)
def test_fault_text_is_parsed(text: str, spec: FaultSpec) -> None:
    assert parse_fault(text) == spec


@pytest.mark.parametrize(
    "text", ["drop", "drop=2", "drop=-0.1", "drop=x", "bogus=0.1", "reset@x", "reset@", "=0.1"]
)
def test_bad_fault_text_is_refused_with_its_text(text: str) -> None:
    with pytest.raises(ValueError, match="bad fault"):
        parse_fault(text)


def test_forced_fault_strikes_the_next_batch_only() -> None:
    plan = FaultPlan()
    plan.force("delay")
    assert plan.for_batch(1, has_reply=True) == ["delay"]
    assert plan.for_batch(2, has_reply=True) == []
    assert plan.injected["delay"] == 1


def test_forcing_an_unknown_kind_is_refused() -> None:
    with pytest.raises(ValueError, match="'jam'"):
        FaultPlan().force("jam")


def test_silent_batch_has_no_reply_to_drop_garble_or_delay() -> None:
    plan = FaultPlan([FaultSpec(k, rate=1.0) for k in FAULT_KINDS])
    assert plan.for_batch(1, has_reply=False) == ["reset", "disconnect", "stall", "extra"]


def test_faults_at_given_batches_strike_only_there() -> None:
    plan = FaultPlan([parse_fault("drop@2,4")])
    struck = [n for n in range(1, 6) if plan.for_batch(n, has_reply=True)]
    assert struck == [2, 4]


def test_same_seed_draws_the_same_faults() -> None:
    def draws(seed: int) -> list[list[str]]:
        plan = FaultPlan([FaultSpec("drop", rate=0.3), FaultSpec("extra", rate=0.3)], seed=seed)
        return [plan.for_batch(n, has_reply=True) for n in range(1, 50)]

    assert draws(7) == draws(7)
    assert any(draws(7))


REPLY = bytes(range(40))


def test_drop_loses_exactly_one_byte() -> None:
    out = FaultPlan(seed=1).mangle_reply(["drop"], REPLY).data
    assert len(out) == len(REPLY) - 1


def test_extra_inserts_one_to_four_bytes() -> None:
    plan = FaultPlan(seed=1)
    lengths = {len(plan.mangle_reply(["extra"], REPLY).data) - len(REPLY) for _ in range(100)}
    assert lengths <= {1, 2, 3, 4}
    assert len(lengths) > 1


def test_extra_after_a_silent_batch_sends_stray_bytes() -> None:
    assert 1 <= len(FaultPlan(seed=1).mangle_reply(["extra"], b"").data) <= 4


def test_stray_bytes_travel_with_the_byte_before_them_and_the_replys_tail() -> None:
    plan = FaultPlan(seed=1)
    for _ in range(100):
        mangled = plan.mangle_reply(["extra"], REPLY)
        stray, cut = len(mangled.data) - len(REPLY), mangled.together_from
        assert 1 <= stray <= 4
        # Paced: an untouched start of the reply. Together: at least its last byte, all
        # the stray bytes, and no gap a pacing could open between them.
        assert mangled.data[:cut] == REPLY[:cut] and cut < len(REPLY)
        assert len(mangled.data[cut:]) == len(REPLY) - cut + stray
    assert plan.mangle_reply(["garble"], REPLY).together_from == len(REPLY)


def test_garble_flips_one_bit_and_keeps_the_length() -> None:
    """faults.py: garble is "a reply of the right length with a wrong value"."""
    out = FaultPlan(seed=1).mangle_reply(["garble"], REPLY).data
    assert len(out) == len(REPLY)
    flipped = sum(bin(a ^ b).count("1") for a, b in zip(out, REPLY, strict=True))
    assert flipped == 1


def test_corrupt_flips_one_bit_of_a_chunk_on_its_way_in() -> None:
    plan = FaultPlan(seed=1)
    plan.force("corrupt")
    chunk = bytes.fromhex("9f bb b3 b2 b1 af 8b 00")
    out, hit = plan.corrupt_chunk(chunk, 1)
    assert hit
    assert sum(bin(a ^ b).count("1") for a, b in zip(out, chunk, strict=True)) == 1
    assert plan.corrupt_chunk(chunk, 2) == (chunk, False)
