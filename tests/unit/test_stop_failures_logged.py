"""A robot whose stop cannot be sent is named in a WARNING, never hidden, and the others
still close: ``ego swarm`` (each emulated robot) and ``ego serve`` (its robot's closers)."""

from __future__ import annotations

import logging

import pytest

from ego.app.swarm import Swarm
from ego.core.backend import Opened
from ego.errors import LinkTimeoutError
from ego.servers.robot import ServedRobot


class _Channel:
    """A channel double whose close sends the stop batch and records that it did."""

    def __init__(self, name: str, fails: bool) -> None:
        self.name = name
        self.fails = fails
        self.closed = False

    def close(self) -> None:
        self.closed = True
        if self.fails:
            raise LinkTimeoutError(f"{self.name}: 0 of 6 reply bytes to the stop batch")


def _warnings(caplog: pytest.LogCaptureFixture) -> list[str]:
    return [r.getMessage() for r in caplog.records if r.levelno == logging.WARNING]


def test_a_swarm_robot_whose_stop_fails_is_named_and_the_others_still_close(
    caplog: pytest.LogCaptureFixture,
) -> None:
    channels = [_Channel("sim0", fails=False), _Channel("sim1", fails=True),
                _Channel("sim2", fails=False)]  # fmt: skip
    swarm = Swarm(3)
    swarm.opened = [Opened(channel) for channel in channels]  # type: ignore[arg-type]
    swarm.close()
    assert all(channel.closed for channel in channels)
    assert _warnings(caplog) == [
        "epuck1: could not stop and close it: sim1: 0 of 6 reply bytes to the stop batch"
    ]


def test_a_served_robot_whose_stop_fails_is_named_and_the_rest_still_closes(
    caplog: pytest.LogCaptureFixture,
) -> None:
    camera, channel = _Channel("camera", fails=False), _Channel("ttyS0", fails=True)
    robot = ServedRobot(channel, closers=[channel.close, camera.close],  # type: ignore[arg-type]
                        name="/dev/ttyS0")  # fmt: skip
    robot.close()
    assert camera.closed
    assert _warnings(caplog) == [
        "/dev/ttyS0: could not stop and close it: ttyS0: 0 of 6 reply bytes to the stop batch"
    ]


def test_a_bug_in_a_closer_is_raised_after_every_closer_ran(
    caplog: pytest.LogCaptureFixture,
) -> None:
    after = _Channel("after", fails=False)

    def broken() -> None:
        raise AttributeError("'NoneType' object has no attribute 'write'")

    robot = ServedRobot(after, closers=[broken, after.close], name="sim")  # type: ignore[arg-type]
    with pytest.raises(AttributeError):
        robot.close()
    assert after.closed
    assert len(_warnings(caplog)) == 1
