"""A Robot changes no process-wide setting unless asked: signals, switch interval, slack."""

from __future__ import annotations

import signal
import sys

import pytest

import ego
from ego.core.safety import TERMINATING_SIGNALS
from ego.core.scheduler import STEPPING_SWITCH_INTERVAL_S, tune_for_stepping


def _handlers() -> dict[signal.Signals, object]:
    return {sig: signal.getsignal(sig) for sig in TERMINATING_SIGNALS}


def test_a_robot_leaves_signal_handlers_and_the_switch_interval_alone() -> None:
    before, interval = _handlers(), sys.getswitchinterval()
    with ego.Robot("sim", seed=1) as robot:
        robot.step(16)
        assert _handlers() == before
        assert sys.getswitchinterval() == interval
    assert _handlers() == before


def test_a_robot_asked_to_handle_signals_installs_them() -> None:
    before = _handlers()
    signal.signal(signal.SIGTERM, signal.SIG_DFL)  # whatever an earlier test left
    try:
        with ego.Robot("sim", seed=1, handle_signals=True):
            assert signal.getsignal(signal.SIGTERM) is not signal.SIG_DFL
    finally:
        for sig, handler in before.items():
            signal.signal(sig, handler)  # type: ignore[arg-type]


def test_tune_for_stepping_shortens_the_switch_interval() -> None:
    saved = sys.getswitchinterval()
    sys.setswitchinterval(0.005)
    try:
        tune_for_stepping()
        assert sys.getswitchinterval() == pytest.approx(STEPPING_SWITCH_INTERVAL_S)
    finally:
        sys.setswitchinterval(saved)
