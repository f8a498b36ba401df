"""The one control session both servers run (lease, deadman, one call in flight), driven by
hand: every event carries its time, no clock is read, no thread runs."""

from __future__ import annotations

import pytest
from helpers import SUBNORMALS
from hypothesis import given
from hypothesis import strategies as st

from ego.servers.sessions.control import ControlSession, Lapsed, Refusal


def held(deadline_s: float = 0.5, who: str = "a", now: float = 0.0) -> ControlSession[str]:
    control: ControlSession[str] = ControlSession(deadline_s)
    assert control.take(who, now)
    return control


def test_the_first_to_take_the_robot_holds_it_and_another_is_refused() -> None:
    control = held()
    assert control.holder == "a"
    assert not control.take("b", 0.1) and not control.admit("b", 0.1)
    assert control.dispatch("b", 0.1) is Refusal.BUSY
    assert control.take("a", 0.2)  # taking it again is fine
    assert control.holder == "a" and control.last_heard == 0.2


def test_nobody_dispatches_before_taking_the_robot() -> None:
    control: ControlSession[str] = ControlSession(0.5)
    assert control.admit("a", 0.0)  # nothing is taken by arriving
    assert control.holder is None and control.dispatch("a", 0.0) is Refusal.BUSY


def test_one_call_in_flight_and_the_next_once_it_completed() -> None:
    control = held()
    assert control.dispatch("a", 0.1) is None
    assert control.dispatch("a", 0.2) is Refusal.IN_FLIGHT
    assert control.completed("a", 0.3)
    assert control.dispatch("a", 0.4) is None


def test_the_deadman_frees_the_robot_just_past_the_deadline() -> None:
    control = held()
    assert control.tick(0.5) is None  # "more than" the deadline
    lapsed = control.tick(0.51)
    assert lapsed == Lapsed("a", pytest.approx(0.51), 0.5)
    assert lapsed is not None and lapsed.why == "silent for 510 ms (deadline 500 ms)"
    assert control.holder is None and control.lapses == 1
    assert control.tick(5.0) is None  # once
    assert control.take("b", 5.0)  # free for another


def test_only_the_holder_keeps_the_deadman_off() -> None:
    control = held()
    control.heard("b", 0.4)
    control.heard("a", 0.3)
    assert control.admit("a", 0.45)  # a request of the holder counts too
    assert control.tick(0.9) is None
    assert control.tick(0.96) is not None


def test_a_running_call_holds_the_deadman_off_and_its_end_restarts_it() -> None:
    control = held()
    assert control.dispatch("a", 0.0) is None
    assert control.tick(10.0) is None and control.due_in(10.0) is None
    assert control.completed("a", 10.0)
    assert control.due_in(10.2) == pytest.approx(0.3)
    assert control.tick(10.4) is None and control.tick(10.6) is not None


def test_releasing_frees_the_robot_and_ends_its_call() -> None:
    control = held()
    assert control.dispatch("a", 0.0) is None
    assert not control.release("b")
    assert control.release("a") and control.holder is None
    assert not control.completed("a", 0.1)  # nobody to answer: the reply is dropped
    assert control.take("b", 0.2) and control.dispatch("b", 0.2) is None


def test_due_in_counts_down_to_the_deadline() -> None:
    control: ControlSession[str] = ControlSession(0.5)
    assert control.due_in(0.0) is None
    control.take("a", 1.0)
    assert control.due_in(1.2) == pytest.approx(0.3)
    assert control.due_in(1.7) == pytest.approx(-0.2)


@given(st.lists(st.tuples(st.sampled_from(["take", "heard", "dispatch", "completed",
                                           "release", "tick"]),
                          st.sampled_from(["a", "b"]),
                          st.floats(0, 0.3, allow_subnormal=SUBNORMALS)), max_size=40))  # fmt: skip
def test_whatever_happens_the_deadman_is_never_late_and_one_call_at_most_runs(
    events: list[tuple[str, str, float]],
) -> None:
    control: ControlSession[str] = ControlSession(0.5)
    now = 0.0
    for name, who, dt in events:
        now += dt
        if name == "tick":
            lapsed = control.tick(now)
            if lapsed is None and control.holder is not None and not control.in_flight:
                assert now - control.last_heard <= 0.5  # not lapsed: not yet due
        elif name == "release":
            control.release(who)
        else:
            getattr(control, name)(who, now)
        assert control.in_flight in (0, 1)
        assert control.holder is not None or control.in_flight == 0
