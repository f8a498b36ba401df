"""Benchmark progress bars stay off when stderr is not a terminal (issue 27: a full run
logged to a file piled up 20,000+ carriage-return fragments with no newline)."""

from __future__ import annotations

import pytest

from benchmarks.common import progress


def test_progress_writes_nothing_when_stderr_is_not_a_terminal(
    capsys: pytest.CaptureFixture[str],
) -> None:
    assert list(progress(range(50), "section", total=50)) == list(range(50))
    assert capsys.readouterr().err == ""
