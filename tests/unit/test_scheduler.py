"""The step clock on a fake clock: absolute deadlines, overruns; the switch interval left alone."""

from __future__ import annotations

import sys
from collections.abc import Iterator

import pytest

from ego.core.scheduler import StepClock


class FakeTime:
    """A clock that only moves when slept on or told to; records every sleep."""

    def __init__(self) -> None:
        self.now = 100.0
        self.sleeps: list[float] = []

    def clock(self) -> float:
        self.now += 1e-6  # reading the clock takes a little time, as it does
        return self.now

    def sleep(self, seconds: float) -> None:
        self.sleeps.append(seconds)
        self.now += seconds

    def work(self, seconds: float) -> None:
        self.now += seconds


@pytest.fixture
def fake() -> FakeTime:
    return FakeTime()


@pytest.fixture
def clock(fake: FakeTime) -> Iterator[StepClock]:
    step_clock = StepClock(spin_s=0.0005, clock=fake.clock, sleep=fake.sleep)
    yield step_clock
    step_clock.close()


def test_steps_end_on_absolute_deadlines_whatever_the_work(
    fake: FakeTime, clock: StepClock
) -> None:
    clock.begin()
    start = fake.now
    for work_s in (0.001, 0.007, 0.0, 0.009):
        fake.work(work_s)
        assert clock.wait(10) is False
    # Four 10 ms steps end 40 ms after the first began, to within the spin's resolution.
    assert fake.now - start == pytest.approx(0.040, abs=1e-4)
    assert clock.overruns == 0


def test_the_wait_sleeps_until_just_before_the_deadline_then_spins(
    fake: FakeTime, clock: StepClock
) -> None:
    clock.begin()
    clock.wait(20)
    assert len(fake.sleeps) == 1
    assert fake.sleeps[0] == pytest.approx(0.020 - 0.0005, abs=1e-4)


def test_an_overrun_is_counted_and_the_next_step_is_not_rushed(
    fake: FakeTime, clock: StepClock
) -> None:
    clock.begin()
    fake.work(0.015)  # a 10 ms step whose work took 15 ms
    assert clock.wait(10) is True
    assert clock.overruns == 1
    assert clock.worst_overrun_s == pytest.approx(0.005, abs=1e-4)
    resumed = fake.now
    clock.wait(10)
    # Re-anchored: the next step lasts its full 10 ms instead of 5 ms of catch-up.
    assert fake.now - resumed == pytest.approx(0.010, abs=1e-4)


def test_a_clock_leaves_the_switch_interval_alone() -> None:
    """One path: only tune_for_stepping (ego run, ego demo) changes the process's setting."""
    before = sys.getswitchinterval()
    clock = StepClock()
    clock.wait(1)
    clock.close()
    assert sys.getswitchinterval() == before
    with pytest.raises(TypeError):
        StepClock(switch_interval_s=0.0002)  # type: ignore[call-arg]
