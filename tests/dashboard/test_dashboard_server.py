"""The dashboard's server on real loopback sockets: who gets in (the token, same origin),
what a page receives, and a controlling page that vanishes mid-drive."""

from __future__ import annotations

import asyncio
import json
import time
from pathlib import Path
from typing import Any

import aiohttp
import pytest
from dashboard_support import served_robot
from helpers import run_async, wait_for_more, wait_until

import ego
from ego.errors import InsecureSecretError
from ego.servers.dashboard.access import dashboard_token, socket_url
from ego.servers.dashboard.live import parse_address
from ego.servers.dashboard.server import SAMPLE_HZ, DashboardServer

SECRET = b"0123456789abcdef0123456789abcdef"


def _ws_url(url: str, token: str | None = None) -> str:
    base = url.split("?")[0].replace("http://", "ws://") + "ws"
    return base + (f"?token={token}" if token else "")


def _jar() -> aiohttp.CookieJar:
    return aiohttp.CookieJar(unsafe=True)  # keeps the cookies of an IP address's page


def _run(coroutine: Any) -> Any:
    return run_async(coroutine)


def _idle(robot: ego.Robot) -> None:
    if not robot.proximity.enabled:
        robot.proximity.enable(32)


def test_off_loopback_a_dashboard_needs_the_secret() -> None:
    with pytest.raises(InsecureSecretError, match="--secret-file"):
        DashboardServer(feed=None, host="0.0.0.0", port=0)  # type: ignore[arg-type]


def test_with_a_secret_only_the_token_opens_it_and_the_url_never_holds_the_secret(
    tmp_path: Path,
) -> None:
    with served_robot(tmp_path, _idle, secret=SECRET) as served:
        token = dashboard_token(SECRET)
        assert served.url.endswith(f"?token={token}")
        assert SECRET.decode() not in served.url
        base = served.url.split("?")[0]

        async def probe() -> list[int]:
            statuses = []
            async with aiohttp.ClientSession(cookie_jar=_jar()) as session:
                for url in (base, base + "?token=" + "0" * 32, served.url, base + "app.js"):
                    async with session.get(url) as response:
                        statuses.append(response.status)
            async with aiohttp.ClientSession() as session:  # not logged in
                for url in (_ws_url(base), _ws_url(base, "f" * 32)):
                    with pytest.raises(aiohttp.WSServerHandshakeError) as info:
                        await session.ws_connect(url)
                    statuses.append(info.value.status)
                async with session.ws_connect(_ws_url(base, token)) as ws:
                    hello = await ws.receive_json()
                    statuses.append(200 if hello["type"] == "hello" else 0)
            return statuses

        # The page's script holds no data: it is public.
        assert _run(probe()) == [403, 403, 200, 200, 403, 403, 200]


def test_a_page_from_another_site_cannot_open_the_socket(tmp_path: Path) -> None:
    with served_robot(tmp_path, _idle) as served:
        port = served.dashboard.server.port  # type: ignore[union-attr]

        async def probe() -> tuple[int, str]:
            async with aiohttp.ClientSession() as session:
                with pytest.raises(aiohttp.WSServerHandshakeError) as info:
                    await session.ws_connect(socket_url(served.url),
                                             headers={"Origin": "http://evil.example"})  # fmt: skip
                own = {"Origin": f"http://127.0.0.1:{port}"}
                async with session.ws_connect(socket_url(served.url), headers=own) as ws:
                    hello = await ws.receive_json()
            return info.value.status, hello["type"]

        assert _run(probe()) == (403, "hello")


def test_a_page_gets_the_robot_the_world_and_samples_at_most_25_a_second(
    tmp_path: Path,
) -> None:
    with served_robot(tmp_path, _idle) as served:

        async def listen() -> tuple[dict[str, Any], list[dict[str, Any]]]:
            async with (
                aiohttp.ClientSession() as session,
                session.ws_connect(socket_url(served.url)) as ws,
            ):
                hello = await ws.receive_json()
                samples = []
                end = time.monotonic() + 1.0
                while time.monotonic() < end:
                    message = json.loads((await ws.receive()).data)
                    if message["type"] == "sample":
                        samples.append(message)
            return hello, samples

        hello, samples = _run(listen())
    assert hello["mode"] == "live" and hello["robot"]["firmware"] == "webots"
    assert hello["world"]["half_x"] == 0.5 and hello["world"]["boxes"] == []
    assert hello["world"]["floor_png"].startswith("data:image/png;base64,")
    assert 10 <= len(samples) <= SAMPLE_HZ + 2  # newest only: a slow page never slows the robot
    assert all(s["proximity"] is not None and len(s["proximity"]) == 8 for s in samples[2:])
    assert samples[-1]["truth"][0] == pytest.approx(0.2, abs=1e-3)


def test_a_controlling_page_that_vanishes_mid_drive_leaves_the_robot_stopped(
    tmp_path: Path,
) -> None:
    def hold_still(robot: ego.Robot) -> None:
        robot.motors.set_speed(0, 0)

    with served_robot(tmp_path, hold_still) as served:

        async def drive_then_vanish() -> None:
            session = aiohttp.ClientSession()
            ws = await session.ws_connect(socket_url(served.url))
            await ws.send_json({"type": "take"})
            for _ in range(5):
                await ws.send_json({"type": "drive", "left": 600, "right": 600})
                await asyncio.sleep(0.1)  # a page's pace of drives, not a wait
            # Gone without a word: the socket is cut, not closed.
            ws._response.connection.transport.abort()  # type: ignore[union-attr]
            await session.close()

        _run(drive_then_vanish())
        assert served.world.speeds == (600, 600) or served.world.snapshot().x_m > 0.2
        assert wait_until(lambda: served.world.speeds == (0, 0), 1.0)
        x = served.world.snapshot().x_m
        # The controller's next 10 steps: each would apply a drive left behind.
        assert wait_for_more(lambda: served.robot.steps, 10)
        assert served.world.snapshot().x_m == pytest.approx(x, abs=1e-4)
        assert served.dashboard.feed.desk.holder is None  # type: ignore[union-attr]


@pytest.mark.parametrize(
    ("text", "address"),
    [
        (None, ("127.0.0.1", 8765)),
        ("0.0.0.0:9000", ("0.0.0.0", 9000)),
        (":9001", ("127.0.0.1", 9001)),
        ("9002", ("127.0.0.1", 9002)),
        ("[::1]:9003", ("::1", 9003)),
        ("robot.local", ("robot.local", 8765)),
    ],
)
def test_dashboard_addresses(text: str | None, address: tuple[str, int]) -> None:
    assert parse_address(text) == address


@pytest.mark.parametrize("text", ["host:port", "host:70000", "[::1]:x"])
def test_a_bad_dashboard_address_is_refused(text: str) -> None:
    with pytest.raises(ValueError, match="HOST:PORT"):
        parse_address(text)
