"""How a replayed run ends (its end is the run's end, at INFO), and begins (a forced firmware).

The end of a replay is told by its type, :class:`ego.errors.ReplayEndedError`, one of the
one error tree's (a LinkLostError, so ``except LinkLostError`` still catches it).
"""

from __future__ import annotations

import logging
from pathlib import Path

import pytest

import ego
from ego.errors import FirmwareMismatchError, LinkLostError, ReplayEndedError
from ego.recording.writer import Recorder

STEPS = 5


@pytest.fixture
def recording(tmp_path: Path) -> Path:
    """Five 32 ms steps of the emulator with the proximity sensors on, recorded."""
    path = tmp_path / "run.mcap"
    recorder = Recorder(path)
    with ego.Robot("sim", seed=3) as robot:
        recorder.attach(robot)
        robot.proximity.enable(32)
        for _ in range(STEPS):
            assert robot.step(32) == 0
        recorder.close()
    return path


def test_the_replays_end_is_a_link_lost_error_of_the_one_tree() -> None:
    assert issubclass(ReplayEndedError, LinkLostError)
    assert ego.errors.__all__.count("ReplayEndedError") == 1


def test_a_replay_that_reaches_its_end_ends_the_run_at_info_not_error(
    recording: Path, caplog: pytest.LogCaptureFixture
) -> None:
    caplog.set_level(logging.INFO, logger="ego")
    with ego.Robot(f"replay://{recording}") as robot:
        robot.proximity.enable(32)
        results = [robot.step(32) for _ in range(STEPS + 1)]
    assert results == [0] * STEPS + [-1]
    ended = [r for r in caplog.records if "link lost for good" in r.getMessage()]
    assert [r.levelno for r in ended] == [logging.INFO]
    assert "the recording ends after step" in ended[0].getMessage()
    assert not [r for r in caplog.records if r.levelno >= logging.ERROR]


def test_a_replay_forced_to_another_firmware_is_a_firmware_mismatch(recording: Path) -> None:
    with pytest.raises(FirmwareMismatchError) as raised:
        ego.Robot(f"replay://{recording}", firmware="gctronic")
    assert str(raised.value) == (
        f"replay://{recording} recorded a robot with the webots firmware, not gctronic"
    )
