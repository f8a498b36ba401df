"""Entry points that answer bad input with a C-style status still say why, in the log.

Webots' ``wbr_init`` returns 0 when it cannot connect, as appendix C.12.2 has it; the
reason must not be lost. (It reopens the faces' default robot, so it cannot be a row of
docs/bad_input.md, whose rows share one.)
"""

from __future__ import annotations

import logging

import pytest

from ego import webots
from ego.faces import default_robot


def test_wbr_init_of_a_missing_port_returns_0_and_logs_why(
    caplog: pytest.LogCaptureFixture,
) -> None:
    try:
        with caplog.at_level(logging.WARNING, logger="ego.webots"):
            assert webots.wbr_init("/dev/ttyNOPE") == 0
        assert webots.wbr_has_failed()
        assert not default_robot.is_open()
        assert "wbr_init('/dev/ttyNOPE') failed: cannot open port '/dev/ttyNOPE'" in caplog.text
    finally:
        default_robot.close()
