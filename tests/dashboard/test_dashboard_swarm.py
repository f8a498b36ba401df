"""A swarm's dashboard in a real headless Chromium: the user picks which robot the page
details (from a list or by clicking it on the map), and the robots' names on the map are
legible and never overlap, even with the robots close together."""

from __future__ import annotations

import json
import threading
from collections.abc import Iterator
from contextlib import ExitStack, contextmanager
from pathlib import Path
from typing import Any

from ego.app.swarm import robot_seed
from ego.core.registry import find_backend, open_port
from ego.errors import RobotResetError
from ego.nursery import Nursery
from ego.seam.batch import Request
from ego.seam.profile import Command, Firmware
from ego.serial.protocol import encode_batch
from ego.servers.dashboard.served import SwarmFeed, WatchedChannel
from ego.servers.dashboard.server import DashboardServer

#: Four robots 8 cm apart, a square in the middle of the arena.
SQUARE = """
box = []
[robot]
x_m = -0.04
y_m = -0.04
[[robots]]
x_m = 0.04
y_m = -0.04
[[robots]]
x_m = -0.04
y_m = 0.04
[[robots]]
x_m = 0.04
y_m = 0.04
"""
NAMES = [f"epuck{k}" for k in range(4)]


def _spin(channel: WatchedChannel, speed: int, stop: threading.Event) -> None:
    """Robot ``k`` turns on the spot at its own speed, reading its proximity sensors."""
    batch = encode_batch(
        [Request(Command.SET_SPEED, (speed, -speed)), Request(Command.PROXIMITY)],
        channel.profile,
    )
    while not stop.wait(0.032):
        try:
            channel.exchange(batch)
        except RobotResetError:  # a loaded machine's resync; the next batch says it all again
            continue


@contextmanager
def swarm_dashboard(tmp_path: Path) -> Iterator[tuple[str, list[Any]]]:
    """Four emulated robots in one world, each spinning at 100 * (k + 1) steps/s, and
    the swarm's dashboard: its URL and the worlds."""
    path = tmp_path / "square.toml"
    path.write_text(SQUARE)
    backend: Any = find_backend("sim")
    worlds = backend.swarm_worlds(str(path), [robot_seed(1, k) for k in range(4)])
    stop = threading.Event()
    with ExitStack() as stack:
        channels = []
        for world in worlds:
            opened = open_port("sim", firmware=Firmware.WEBOTS, world=world)
            stack.callback(opened.close)
            channels.append(WatchedChannel(opened.channel, world=opened.ground_truth))
        feed = SwarmFeed(NAMES, channels)
        server = stack.enter_context(DashboardServer(feed, "127.0.0.1", 0))
        feed.server = server
        feed.start()
        stack.callback(feed.close)
        threads = stack.enter_context(Nursery("the test's spinning robots", join_s=5))
        stack.callback(stop.set)  # first: then the nursery joins them
        for k, channel in enumerate(channels):
            threads.start_thread(_spin, channel, 100 * (k + 1), stop, name=f"test-spin-{k}")
        yield server.url, worlds


def _open(page: Any, url: str) -> None:
    page.goto(url)
    page.wait_for_function("document.getElementById('link-status').textContent === 'live'")
    page.wait_for_function("document.getElementById('map').dataset.labels !== undefined")


def test_the_user_picks_the_robot_the_page_details(tmp_path: Path, page: Any) -> None:
    with swarm_dashboard(tmp_path) as (url, _):
        _open(page, url)
        options = page.eval_on_selector_all("#robot-pick option", "(o) => o.map((x) => x.value)")
        page.wait_for_function("document.getElementById('speed-left').textContent === '100'")
        page.select_option("#robot-pick", "epuck2")
        page.wait_for_function("document.getElementById('speed-left').textContent === '300'")
        named = page.inner_text("#robot-name")
        right = page.inner_text("#speed-right")
        # Clicking a robot on the map details it too.
        x, y = page.evaluate("mapPoint(...view.swarm.find((r) => r[0] === 'epuck3').slice(1, 3))")
        page.click("#map", position={"x": x, "y": y})
        page.wait_for_function("document.getElementById('speed-left').textContent === '400'")
        picked = page.input_value("#robot-pick")
    assert options == NAMES
    assert named == "epuck2" and right == "-300"
    assert picked == "epuck3"


def test_the_names_on_the_map_are_legible_and_never_overlap(tmp_path: Path, page: Any) -> None:
    with swarm_dashboard(tmp_path) as (url, _):
        _open(page, url)
        labels = json.loads(page.get_attribute("#map", "data-labels") or "[]")
        size_px = float(page.get_attribute("#map", "data-label-px") or 0)
        width = page.evaluate("document.getElementById('map').clientWidth")
    assert len(labels) == 4
    assert size_px >= 12  # CSS pixels, whatever the canvas's size
    for i, (ax, ay, aw, ah) in enumerate(labels):
        assert ax >= 0 and ax + aw <= width + 0.5
        for bx, by, bw, bh in labels[i + 1 :]:
            assert ax + aw <= bx or bx + bw <= ax or ay + ah <= by or by + bh <= ay, labels
