"""The Zenoh channel at the seam: wrappers forward its session (a recorded robot's radio
shares it rather than open a second one), and its keepalive thread has an owner: it is
joined at close, and a failure of it is told at the next exchange, never lost."""

from __future__ import annotations

import threading
import time
from pathlib import Path

import pytest
import zenoh
from helpers import wait_until
from zenoh_support import client_session, served_node

import ego
from ego.backends.zenoh_remote import ZenohChannel
from ego.controller.radio import RobotRadio
from ego.core.environment import read_environment
from ego.errors import LinkLostError
from ego.recording.writer import Recorder
from ego.seam.batch import Request
from ego.seam.channel import TappedChannel
from ego.seam.profile import Command
from ego.serial.protocol import encode_batch
from ego.servers.dashboard.served import WatchedChannel


def _keepalives() -> list[threading.Thread]:
    return [t for t in threading.enumerate() if t.name == "ego-zenoh-keepalive"]


def test_wrappers_forward_the_zenoh_session_of_the_channel_they_wrap() -> None:
    with served_node("seam1") as served:
        session = client_session(served.endpoint)
        channel = ZenohChannel("seam1", session)
        try:
            wrapped = WatchedChannel(TappedChannel(channel, lambda batch, reply: None))
            assert wrapped.session_of(zenoh.Session) is session
            assert wrapped.name == "zenoh://seam1"
        finally:
            channel.close()


def test_a_recorded_zenoh_robot_s_radio_shares_its_session(tmp_path: Path) -> None:
    """Issue 24: once a recording wrapped the channel, the radio opened a second session."""
    with (
        served_node("seam2") as served,
        ego.Robot("zenoh://seam2", zenoh_connect=[served.endpoint]) as robot,
    ):
        recorder = Recorder(tmp_path / "run.mcap")
        recorder.attach(robot)
        try:
            assert isinstance(robot.channel, TappedChannel)
            radio = RobotRadio(robot, read_environment({})).get()
            assert radio.session is robot.channel.session_of(zenoh.Session)
            assert radio.session is not None
        finally:
            recorder.close()


def test_close_joins_the_keepalive_thread() -> None:
    with served_node("seam3") as served:
        before = set(_keepalives())
        channel = ZenohChannel("seam3", client_session(served.endpoint))
        channel.waiting_until(time.monotonic() + 5.0)
        started = set(_keepalives()) - before
        assert len(started) == 1
        channel.close()
        assert not any(thread.is_alive() for thread in started)


def test_a_failed_keepalive_is_told_at_the_next_exchange() -> None:
    with served_node("seam4") as served:
        session = client_session(served.endpoint)
        channel = ZenohChannel("seam4", session, owns_session=False)
        batch = encode_batch([Request(Command.GET_SPEED)], channel.profile)
        channel.exchange(batch)
        channel.waiting_until(time.monotonic() + 30.0)
        session.close()  # the session goes away under the keepalive
        assert wait_until(lambda: channel.keepalive_failure is not None)
        assert not [t for t in _keepalives() if t.is_alive()]  # it ended, and said why
        with pytest.raises(LinkLostError, match=r"keepalive failed.*session closed"):
            channel.exchange(batch)
