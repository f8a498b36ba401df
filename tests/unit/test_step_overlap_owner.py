"""Issue 35: the stepBegin thread is its StepOverlap's (a Nursery's): the robot's close
waits for a step in flight, and a step begun once the robot closed starts no thread."""

from __future__ import annotations

import threading

import pytest
from helpers import wait_until

from ego.controller.step_overlap import StepOverlap


def test_close_waits_for_the_step_in_flight() -> None:
    entered, closing, go, finished = (threading.Event() for _ in range(4))

    def step(duration: int | None) -> int:
        entered.set()
        go.wait(10)
        finished.set()
        return 32

    overlap = StepOverlap(step)
    before = set(threading.enumerate())
    overlap.begin(32)
    assert entered.wait(10)
    (thread,) = set(threading.enumerate()) - before

    def let_it_finish() -> None:  # only once close has begun: close must wait for it
        assert wait_until(closing.is_set, timeout_s=10)
        go.set()

    helper = threading.Thread(target=let_it_finish)
    helper.start()
    closing.set()
    overlap.close()
    assert finished.is_set() and not thread.is_alive()
    helper.join(10)
    assert overlap.end() == 32  # its result is still the controller's to take


def test_a_step_begun_after_close_runs_at_once_without_a_thread() -> None:
    steps: list[str] = []

    def step(duration: int | None) -> int:
        steps.append(threading.current_thread().name)
        return -1  # what a closed robot's step answers

    overlap = StepOverlap(step)
    overlap.close()
    overlap.begin(32)
    assert not overlap.in_flight
    assert steps == [threading.current_thread().name]
    assert overlap.end() == -1
    assert overlap.end() == 0  # none begun since


def test_a_step_error_is_raised_at_end_once_closed_too() -> None:
    def step(duration: int | None) -> int:
        raise RuntimeError("the link broke")

    overlap = StepOverlap(step)
    overlap.close()
    overlap.begin(32)
    with pytest.raises(RuntimeError, match="the link broke"):
        overlap.end()
