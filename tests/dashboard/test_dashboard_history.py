"""A page opened late gets the last minute: the server keeps a sample every 0.1 s whether
or not a page watches, and sends them as the page connects; its plot and path start
there, not empty."""

from __future__ import annotations

import asyncio
import json
from pathlib import Path
from typing import Any

import aiohttp
from dashboard_support import served_robot
from helpers import run_async, wait_until

import ego
from ego.servers.dashboard.access import socket_url
from ego.servers.dashboard.history import History


class Clock:
    def __init__(self) -> None:
        self.now = 100.0

    def __call__(self) -> float:
        return self.now


def _feed(history: History, clock: Clock, seconds: float, rate_hz: float, t0: float = 0.0) -> None:
    """Offer ``history`` samples at ``rate_hz`` for ``seconds`` of run (and wall) time."""
    for k in range(round(seconds * rate_hz)):
        history.add({"t": t0 + k / rate_hz})
        clock.now += 1 / rate_hz


def test_it_keeps_ten_samples_a_second_for_the_last_minute() -> None:
    clock = Clock()
    history = History(clock=clock)
    _feed(history, clock, 90.0, 25.0)  # a minute and a half at 25 samples a second
    times = [s["t"] for s in history.samples()]
    assert times[-1] - times[0] <= 60.0
    assert times[-1] - times[0] > 59.5  # the whole minute, no more
    assert 590 <= len(times) <= 610  # ten a second
    assert times == sorted(times)


def test_it_starts_afresh_when_the_run_time_goes_back() -> None:
    clock = Clock()
    history = History(clock=clock)
    _feed(history, clock, 5.0, 25.0, t0=30.0)
    _feed(history, clock, 1.0, 25.0, t0=2.0)  # a replay sought back to 2 s
    times = [s["t"] for s in history.samples()]
    assert times[0] == 2.0 and times[-1] < 3.0


def test_due_says_when_a_sample_would_be_kept() -> None:
    clock = Clock()
    history = History(clock=clock)
    assert history.due()
    history.add({"t": 0.0})
    assert not history.due()
    clock.now += 0.1
    assert history.due()


def _drive(robot: ego.Robot) -> None:
    if not robot.proximity.enabled:
        robot.proximity.enable(32)
    robot.motors.set_speed(200, 200)


async def _first_messages(url: str) -> tuple[dict[str, Any], dict[str, Any], dict[str, Any]]:
    """The hello, the history and the first sample a page gets."""
    ws_url = socket_url(url)  # the socket's URL, with the page's token
    async with aiohttp.ClientSession() as session, session.ws_connect(ws_url) as ws:
        hello = await ws.receive_json()
        history = await ws.receive_json()
        while True:
            message = json.loads((await asyncio.wait_for(ws.receive(), 5)).data)
            if message["type"] == "sample":
                return hello, history, message


def test_a_socket_opened_late_gets_the_seconds_before_it(tmp_path: Path) -> None:
    with served_robot(tmp_path, _drive, world=_WIDE) as served:
        assert wait_until(lambda: served.robot.time_s > 3.0, 20)  # no page meanwhile
        hello, history, sample = run_async(_first_messages(served.url))
    assert hello["type"] == "hello" and history["type"] == "history"
    samples = history["samples"]
    times = [s["t"] for s in samples]
    assert times[0] < 0.5 and times[-1] > 2.9  # from the run's start, without a page open
    assert times == sorted(times) and times[-1] <= sample["t"]
    assert 15 <= len(samples) <= 11 * times[-1] + 2  # about ten a second
    # The robot drove meanwhile: the history holds its path.
    assert samples[-1]["odometry"][0] > samples[0]["odometry"][0] + 0.03


def test_a_page_opened_late_plots_and_draws_the_path_from_before(tmp_path: Path, page: Any) -> None:
    with served_robot(tmp_path, _drive, world=_WIDE) as served:
        assert wait_until(lambda: served.robot.time_s > 4.0, 20)
        opened_at = served.robot.time_s
        page.goto(served.url)
        page.wait_for_function("document.getElementById('link-status').textContent === 'live'")
        page.wait_for_function("view.history.length > 20")
        first = page.evaluate("view.history[0].t")
        trace = page.evaluate("view.odometry.length")
        page.wait_for_function("document.getElementById('plot').dataset.yTicks !== undefined")
    assert first < opened_at - 3.0, (first, opened_at)  # the plot starts seconds before the page
    assert trace > 30  # and so does the path


#: A wide open arena: the robot drives straight for seconds without meeting a wall.
_WIDE = """
box = []
[arena]
size_m = 3.0
[robot]
x_m = -1.0
y_m = 0.0
heading_deg = 0
"""
