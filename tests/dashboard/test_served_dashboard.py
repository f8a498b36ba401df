"""``ego serve --dashboard``: the page sees what the PC's controller reads and asks, and
its stop holds the robot whatever the controller keeps sending."""

from __future__ import annotations

import asyncio
import json
import threading
import time
from collections.abc import Iterator
from contextlib import ExitStack
from typing import Any

import aiohttp
import pytest
from fakes import FAST_LINK
from helpers import run_async, wait_for_more, wait_until

import ego
from ego.nursery import Nursery
from ego.serial.link import Link
from ego.serial.transport import SerialTransport
from ego.servers.dashboard.access import socket_url
from ego.servers.dashboard.served import ServedFeed, WatchedChannel
from ego.servers.dashboard.server import DashboardServer
from ego.servers.socket.server import Server
from ego.servers.socket.server_thread import ServerThread
from firmware_sim import Emulator
from firmware_sim.ego_backend import EmulatorTruth


@pytest.fixture
def served() -> Iterator[tuple[Emulator, DashboardServer, list[tuple[int, int]]]]:
    """An emulator served over TCP with a dashboard, and a client robot driving it at the
    speeds in the returned list's first item."""
    with ExitStack() as stack:
        emu = stack.enter_context(Emulator("webots", seed=1))
        link = Link(SerialTransport(emu.path), settings=FAST_LINK)
        stack.callback(link.close)
        watched = WatchedChannel(link, world=EmulatorTruth(emu.world, emu))
        feed = ServedFeed(watched, emu.path)
        board = stack.enter_context(DashboardServer(feed, "127.0.0.1", 0))
        feed.server = board
        thread = stack.enter_context(ServerThread(Server(watched, listen=["tcp://127.0.0.1:0"])))
        speeds = [(500, 500)]
        stop = threading.Event()
        failures: list[BaseException] = []

        def controller() -> None:
            try:
                with ego.Robot(thread.url) as robot:
                    robot.proximity.enable(32)
                    while not stop.is_set() and robot.step(32) != -1:
                        robot.motors.set_speed(*speeds[0])
            except BaseException as exc:  # reported by the test
                failures.append(exc)

        threads = stack.enter_context(Nursery("the test's controller", join_s=10))
        stack.callback(stop.set)  # first: then the nursery joins it
        threads.start_thread(controller, name="test-controller")
        assert wait_until(lambda: emu.world.speeds == (500, 500), 5)
        yield emu, board, speeds
        assert not failures, failures  # the controller ran until the test ended it


async def _page(board: DashboardServer, script: list[dict[str, Any]]) -> dict[str, Any]:
    """Open the page's socket, read the hello and a sample, send ``script``; what came."""
    seen: dict[str, Any] = {"errors": []}
    async with aiohttp.ClientSession() as session, session.ws_connect(socket_url(board.url)) as ws:
        seen["hello"] = await ws.receive_json()
        while "sample" not in seen:
            message = json.loads((await ws.receive()).data)
            if message["type"] == "sample" and message["proximity"] is not None:
                seen["sample"] = message
        for command in script:
            await ws.send_json(command)
        end = time.monotonic() + 0.5
        while time.monotonic() < end:
            try:
                received = await ws.receive(timeout=0.1)
            except asyncio.TimeoutError:
                continue
            message = json.loads(received.data)
            if message["type"] == "error":
                seen["errors"].append(message["error"])
    return seen


def test_the_page_sees_what_the_pcs_controller_reads_and_asks(served: Any) -> None:
    emu, board, _ = served
    seen = run_async(_page(board, []))
    assert seen["hello"]["mode"] == "served"
    assert seen["hello"]["robot"]["proximity_count"] == 8
    assert seen["hello"]["world"] is not None
    sample = seen["sample"]
    assert sample["speed"] == [500, 500] and len(sample["proximity"]) == 8
    assert sample["truth"][0] == pytest.approx(emu.world.snapshot().x_m, abs=0.05)


def test_its_stop_holds_the_robot_while_the_controller_keeps_driving(served: Any) -> None:
    emu, board, speeds = served
    seen = run_async(_page(board, [
        {"type": "take"},
        {"type": "drive", "left": 100, "right": 100},
        {"type": "stop"},
    ]))  # fmt: skip
    assert any("controller runs on the PC" in e for e in seen["errors"])
    assert wait_until(lambda: emu.world.speeds == (0, 0), 0.5)
    # The PC's controller goes on stepping: the stop holds over 15 of its batches
    # reaching the robot, however long they take. (Its 500 went out once: ego sends a
    # speed only when it changes.)
    assert wait_for_more(lambda: len(emu.history), 15), "the controller stopped stepping"
    assert emu.world.speeds == (0, 0)
    run_async(_page(board, [{"type": "take"}, {"type": "resume"}]))
    assert wait_until(lambda: emu.world.speeds == tuple(speeds[0]), 2)


def test_a_controller_that_changes_speed_while_stopped_runs_on(served: Any) -> None:
    """The stop holds a new speed too, and the controller is not told its D went wrong:
    the speed echo confirming it says what it asked (before, the echo said 0, 0, the
    controller asked again three times and ended with a ProtocolError)."""
    emu, board, speeds = served
    run_async(_page(board, [{"type": "take"}, {"type": "stop"}]))
    assert wait_until(lambda: emu.world.speeds == (0, 0), 0.5)
    asked = len(emu.history)
    speeds[0] = (-300, 200)  # the controller sends it at its next step
    assert wait_until(lambda: any("D" in r.commands for r in list(emu.history)[asked:]))
    assert wait_for_more(lambda: len(emu.history), 15), "the controller stopped stepping"
    assert emu.world.speeds == (0, 0)  # held
    run_async(_page(board, [{"type": "take"}, {"type": "resume"}]))
    assert wait_until(lambda: emu.world.speeds == (-300, 200), 2)  # what it asked last

