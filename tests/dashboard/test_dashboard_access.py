"""Who gets into a dashboard, over real loopback sockets: the token logs a browser in with
a cookie and leaves the URL, nothing live answers without it (loopback included), a
request for another Host is refused, every response forbids framing, the pages are
capped, and a command nested too deep is answered, not raised."""

from __future__ import annotations

import logging
import socket
from pathlib import Path
from typing import Any

import aiohttp
import pytest
from dashboard_support import served_robot
from helpers import run_async, wait_until

import ego
from ego.servers.dashboard.access import Gate, socket_url
from ego.servers.dashboard.server import MAX_PAGES, DashboardServer

SECRET = b"0123456789abcdef0123456789abcdef"


def _idle(robot: ego.Robot) -> None:
    robot.motors.set_speed(0, 0)


def _base(url: str) -> str:
    return url.split("?")[0]


def _jar() -> aiohttp.CookieJar:
    return aiohttp.CookieJar(unsafe=True)  # keeps the cookies of an IP address's page


def test_the_token_url_sets_a_strict_httponly_cookie_and_redirects_to_the_bare_page(
    tmp_path: Path,
) -> None:
    with served_robot(tmp_path, _idle) as served:

        async def login() -> tuple[int, str, str, int, str]:
            async with aiohttp.ClientSession(cookie_jar=_jar()) as session:
                async with session.get(served.url, allow_redirects=False) as response:
                    status, location = response.status, response.headers.get("Location", "")
                    cookie = response.headers.get("Set-Cookie", "")
                async with session.get(_base(served.url)) as page:
                    return status, location, cookie, page.status, await page.text()

        status, location, cookie, page_status, html = run_async(login())
    assert (status, location) == (303, "./")  # the token leaves the URL bar
    assert "HttpOnly" in cookie and "SameSite=Strict" in cookie and "Path=/" in cookie
    assert page_status == 200 and "<script src=\"app.js\">" in html


def test_on_loopback_too_nothing_live_answers_without_the_token(tmp_path: Path) -> None:
    with served_robot(tmp_path, _idle) as served:
        assert "?token=" in served.url
        base = _base(served.url)
        wrong = socket_url(base + "?token=" + "0" * 32)
        cookie = served.dashboard.server.gate.cookie_name  # type: ignore[union-attr]

        async def probe() -> list[int]:
            statuses = []
            async with aiohttp.ClientSession() as session:  # never logged in
                for url in (base, base + "?token=" + "0" * 32):
                    async with session.get(url, allow_redirects=False) as response:
                        statuses.append(response.status)
                for ws_url, cookies in ((socket_url(base), {}), (wrong, {}),
                                        (socket_url(base), {cookie: "0" * 32})):  # fmt: skip
                    session.cookie_jar.update_cookies(cookies)
                    with pytest.raises(aiohttp.WSServerHandshakeError) as refused:
                        await session.ws_connect(ws_url)
                    statuses.append(refused.value.status)
            return statuses

        assert run_async(probe()) == [403, 403, 403, 403, 403]


def test_the_socket_opens_with_the_login_cookie_alone(tmp_path: Path) -> None:
    with served_robot(tmp_path, _idle, secret=SECRET) as served:

        async def visit() -> str:
            async with aiohttp.ClientSession(cookie_jar=_jar()) as session:
                async with session.get(served.url):
                    pass
                async with session.ws_connect(socket_url(_base(served.url))) as ws:
                    return str((await ws.receive_json())["type"])

        assert run_async(visit()) == "hello"


def test_a_navigation_from_another_site_without_the_cookie_is_asked_again_not_served(
    tmp_path: Path,
) -> None:
    with served_robot(tmp_path, _idle) as served:

        async def land() -> tuple[int, str]:
            async with (
                aiohttp.ClientSession() as session,
                session.get(_base(served.url), headers={"Sec-Fetch-Site": "cross-site"}) as page,
            ):
                return page.status, await page.text()

        status, html = run_async(land())
    assert status == 200 and '<meta http-equiv="refresh" content="0">' in html
    assert "app.js" not in html  # nothing of the page until it asks from its own origin


def test_a_request_for_a_name_not_the_dashboards_is_refused_even_with_the_token(
    tmp_path: Path,
) -> None:
    """DNS rebinding: evil.test made to resolve to 127.0.0.1 reaches the server with its
    own name in Host."""
    with served_robot(tmp_path, _idle) as served:
        port = served.dashboard.server.port  # type: ignore[union-attr]
        token = served.dashboard.server.token  # type: ignore[union-attr]
        evil = {"Host": f"evil.test:{port}", "Origin": f"http://evil.test:{port}"}

        async def probe() -> list[tuple[int, str]]:
            seen = []
            async with aiohttp.ClientSession() as session:
                for path in (f"/?token={token}", "/app.js", f"/ws?token={token}"):
                    url = _base(served.url).rstrip("/") + path
                    async with session.get(url, headers=evil, allow_redirects=False) as response:
                        seen.append((response.status, await response.text()))
            return seen

        seen = run_async(probe())
    assert [status for status, _ in seen] == [421, 421, 421]
    assert "'evil.test:" in seen[0][1] and "is not a name of this dashboard" in seen[0][1]


def test_every_response_forbids_framing_sniffing_and_referrers(tmp_path: Path) -> None:
    with served_robot(tmp_path, _idle) as served:
        base = _base(served.url)

        async def headers() -> list[Any]:
            async with aiohttp.ClientSession(cookie_jar=_jar()) as session:
                seen = []
                for url in (served.url, base + "app.js", base + "?token=bad"):
                    async with session.get(url) as response:
                        seen.append(response.headers)
                return seen

        for got in run_async(headers()):
            policy = got.get("Content-Security-Policy", "")
            assert "frame-ancestors 'none'" in policy and "script-src 'self'" in policy
            assert got.get("X-Frame-Options") == "DENY"
            assert got.get("X-Content-Type-Options") == "nosniff"
            assert got.get("Referrer-Policy") == "no-referrer"


def test_the_pages_are_capped_and_a_closed_one_frees_its_place(tmp_path: Path) -> None:
    with served_robot(tmp_path, _idle) as served:
        ws_url = socket_url(served.url)
        board = served.dashboard.server
        assert board is not None

        async def flood() -> tuple[int, str]:
            async with aiohttp.ClientSession() as session:
                sockets = [await session.ws_connect(ws_url) for _ in range(MAX_PAGES)]
                with pytest.raises(aiohttp.WSServerHandshakeError) as refused:
                    await session.ws_connect(ws_url)
                await sockets.pop().close()
                # The server's count of pages (what its cap reads) gives the place back.
                assert wait_until(lambda: board._admitted < MAX_PAGES)
                async with session.ws_connect(ws_url) as ws:
                    again = (await ws.receive_json())["type"]
                for ws in sockets:
                    await ws.close()
            return refused.value.status, again

        status, again = run_async(flood())
    assert status == 503 and again == "hello"


def test_a_command_nested_too_deep_is_answered_and_the_page_goes_on(
    tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    with served_robot(tmp_path, _idle) as served:

        async def nest() -> tuple[str, str]:
            async with (
                aiohttp.ClientSession() as session,
                session.ws_connect(socket_url(served.url)) as ws,
            ):
                await ws.send_str("[" * 2000 + "]" * 2000)
                error = ""
                while not error:
                    message = await ws.receive_json()
                    error = message.get("error", "") if message["type"] == "error" else ""
                await ws.send_json({"type": "take"})
                role = ""
                while role != "control":
                    message = await ws.receive_json()
                    role = message.get("role", "") if message["type"] == "state" else role
                return error, role

        with caplog.at_level(logging.ERROR):
            error, role = run_async(nest())
    assert "a command is one JSON object of at most 4096 bytes" in error
    assert role == "control"  # the same socket still serves
    assert not [r for r in caplog.records if r.levelno >= logging.ERROR]  # no traceback


@pytest.mark.parametrize(
    ("bind", "host", "allowed"),
    [
        ("127.0.0.1", "127.0.0.1:8765", True),
        ("127.0.0.1", "localhost:8765", True),
        ("127.0.0.1", "[::1]:8765", True),
        ("127.0.0.1", "127.0.0.2", True),  # an address literal: never a rebinding
        ("127.0.0.1", "evil.test:8765", False),
        ("127.0.0.1", "127.0.0.1.evil.test", False),
        ("127.0.0.1", "", False),
        ("0.0.0.0", socket.gethostname(), True),
        ("0.0.0.0", "evil.test", False),
        ("robot.local", "ROBOT.LOCAL:8765", True),
    ],
)
def test_the_host_allow_list(bind: str, host: str, allowed: bool) -> None:
    assert Gate(bind, SECRET).host_ok(host) is allowed


def test_a_rebound_page_is_not_its_own_origin() -> None:
    gate = Gate("127.0.0.1", None)
    assert gate.origin_ok("http://127.0.0.1:8765", "127.0.0.1:8765")
    assert not gate.origin_ok("http://evil.test:8765", "evil.test:8765")
    assert not gate.origin_ok("http://evil.test:8765", "127.0.0.1:8765")


def test_a_wildcard_bind_prints_this_machines_name_and_opens_by_a_loopback_address() -> None:
    board = DashboardServer(feed=None, host="0.0.0.0", port=0, secret=SECRET)  # type: ignore[arg-type]
    with board:
        assert "0.0.0.0" not in board.url
        assert board.url.startswith(f"http://{socket.gethostname()}:{board.port}/?token=")
        via = board.url.replace(socket.gethostname(), "127.0.0.2", 1)

        async def visit() -> tuple[int, str]:
            async with (
                aiohttp.ClientSession(cookie_jar=_jar()) as session,
                session.get(via) as response,
            ):
                return response.status, str(response.url)

        status, landed = run_async(visit())
    assert status == 200 and landed == f"http://127.0.0.2:{board.port}/"
