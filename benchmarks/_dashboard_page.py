"""A page's WebSocket, without a browser: ``python -m benchmarks._dashboard_page URL``
reads every message the dashboard sends until killed (the benchmark's one page)."""

from __future__ import annotations

import asyncio
import sys

import aiohttp

from ego.servers.dashboard.access import socket_url


async def main(url: str) -> None:
    ws_url = socket_url(url)
    async with aiohttp.ClientSession() as session, session.ws_connect(ws_url) as ws:
        print("connected", flush=True)
        async for _ in ws:
            pass


if __name__ == "__main__":
    asyncio.run(main(sys.argv[1]))
