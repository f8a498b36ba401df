"""A dashboard on loopback and the requests the bad-input table sends it: what a browser
or a script would send, answered with the HTTP status and the text a person reads."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import aiohttp
from helpers import run_async

from ego.servers.dashboard.access import socket_url
from ego.servers.dashboard.server import DashboardServer, Feed


@dataclass(frozen=True)
class HttpAnswer:
    """A dashboard's answer: its status (101: the socket opened) and the text it said."""

    status: int
    text: str


class DashboardProbe:
    """A dashboard of ``feed`` on 127.0.0.1 (any free port), for the table's rows."""

    def __init__(self, feed: Feed) -> None:
        self.server = DashboardServer(feed, "127.0.0.1", 0)
        self.base = ""

    def __enter__(self) -> DashboardProbe:
        self.server.start()
        self.base = f"http://127.0.0.1:{self.server.port}"
        return self

    def __exit__(self, *exc: object) -> None:
        self.server.close()

    def get(self, path: str, host: str | None = None) -> HttpAnswer:
        """``GET path`` as a browser that never logged in sends it (``host``: its Host)."""
        headers = {"Host": host} if host else {}

        async def get() -> HttpAnswer:
            async with (
                aiohttp.ClientSession() as session,
                session.get(self.base + path, headers=headers, allow_redirects=False) as answer,
            ):
                return HttpAnswer(answer.status, await answer.text())

        return run_async(get())  # type: ignore[no-any-return]

    def sockets(self, count: int) -> HttpAnswer:
        """Open ``count`` sockets with the token at once: the first refusal, if any."""

        async def flood() -> HttpAnswer:
            opened: list[Any] = []
            async with aiohttp.ClientSession() as session:
                try:
                    for _ in range(count):
                        opened.append(await session.ws_connect(socket_url(self.server.url)))
                except aiohttp.WSServerHandshakeError:
                    # Refused: once more as a plain request, to read what it says.
                    plain = socket_url(self.server.url).replace("ws", "http", 1)
                    async with session.get(plain) as answer:
                        return HttpAnswer(answer.status, await answer.text())
                finally:
                    for ws in opened:
                        await ws.close()
            return HttpAnswer(101, "")

        return run_async(flood())  # type: ignore[no-any-return]

    def send(self, text: str) -> HttpAnswer:
        """Send ``text`` on a socket with the token: the first error it is answered."""

        async def send() -> HttpAnswer:
            async with (
                aiohttp.ClientSession() as session,
                session.ws_connect(socket_url(self.server.url)) as ws,
            ):
                await ws.send_str(text)
                while True:
                    message = await ws.receive_json()
                    if message["type"] == "error":
                        return HttpAnswer(101, str(message["error"]))

        return run_async(send())  # type: ignore[no-any-return]
