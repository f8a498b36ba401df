"""The dashboard's web server: the page, and a WebSocket per browser, on a thread of its own.

aiohttp serves both (one maintained asyncio library for HTTP and WebSockets, which the
rest of ego's asyncio code already fits). The server knows nothing of robots: a
:class:`Feed` gives it the first message a page gets, handles the pages' commands, and
pushes samples and camera frames through :meth:`DashboardServer.publish` and
:meth:`DashboardServer.publish_image`, from any thread. Pages get at most
:data:`SAMPLE_HZ` samples and :data:`IMAGE_HZ` frames a second, the newest ones: a
slow browser skips frames, it never slows the robot.
"""

from __future__ import annotations

import asyncio
import contextlib
import itertools
import json
import logging
import threading
import time
from importlib import resources
from typing import Any, Protocol

from aiohttp import WSMsgType, web

from ego.dashboard.access import check_binding, dashboard_token, same_origin, token_matches
from ego.dashboard.control import Reply
from ego.dashboard.history import History

__all__ = ["IMAGE_HZ", "JPEG_QUALITY", "SAMPLE_HZ", "DashboardServer", "Feed"]

log = logging.getLogger(__name__)

SAMPLE_HZ = 25
IMAGE_HZ = 10
JPEG_QUALITY = 80
_STATIC = ("index.html", "app.js", "style.css")
_TYPES = {".html": "text/html", ".js": "text/javascript", ".css": "text/css"}


class Feed(Protocol):
    """What the server shows and obeys: a live robot, or a recording played back."""

    def hello(self) -> dict[str, Any]: ...

    def state(self, client: object) -> dict[str, Any]: ...

    def handle(self, client: object, message: object) -> Reply: ...

    def leave(self, client: object) -> None: ...

    def stop_now(self) -> None: ...


class DashboardServer:
    """Serves ``feed`` at http://HOST:PORT/ until closed (``port`` 0: any free port)."""

    def __init__(
        self, feed: Feed, host: str = "127.0.0.1", port: int = 8765,
        secret: bytes | None = None,
    ) -> None:  # fmt: skip
        check_binding(host, secret)
        self.feed = feed
        self.host = host
        self.token = dashboard_token(secret) if secret is not None else None
        self._port = port
        self._clients: dict[int, web.WebSocketResponse] = {}
        self._ids = itertools.count(1)
        self._sample: dict[str, Any] | None = None
        self._image: bytes | None = None
        self._frame: Any = None
        self._sent_sample = self._sent_image = 0.0
        self._loop: asyncio.AbstractEventLoop | None = None
        self._runner: web.AppRunner | None = None
        self._thread: threading.Thread | None = None
        self._ready = threading.Event()
        self._failure: BaseException | None = None
        self._wake: asyncio.Event | None = None
        self._stopping = False
        #: The last minute of samples, sent to each page as it connects.
        self.history = History()

    # -- life --------------------------------------------------------------------------------

    def start(self) -> DashboardServer:
        """Start serving; raises OSError at once when the address cannot be bound."""
        self._thread = threading.Thread(target=self._serve, name="ego-dashboard", daemon=True)
        self._thread.start()
        self._ready.wait(10)
        if self._failure is not None:
            raise self._failure
        return self

    @property
    def port(self) -> int:
        return self._port

    @property
    def url(self) -> str:
        host = f"[{self.host}]" if ":" in self.host else self.host
        query = f"?token={self.token}" if self.token else ""
        return f"http://{host}:{self._port}/{query}"

    @property
    def client_count(self) -> int:
        return len(self._clients)

    def close(self) -> None:
        loop, thread = self._loop, self._thread
        if loop is None or thread is None:
            return
        with contextlib.suppress(RuntimeError):  # the loop already ended
            asyncio.run_coroutine_threadsafe(self._shutdown(), loop).result(5)
        thread.join(5)
        self._loop = self._thread = None

    def __enter__(self) -> DashboardServer:
        return self.start()

    def __exit__(self, *exc: object) -> None:
        self.close()

    def _serve(self) -> None:
        loop = asyncio.new_event_loop()
        self._loop = loop
        try:
            loop.run_until_complete(self._open())
        except BaseException as exc:  # the address is taken, say: start() raises it
            self._failure = exc
            self._ready.set()
            loop.close()
            return
        self._ready.set()
        try:
            loop.run_until_complete(self._pump())
        finally:
            loop.close()

    async def _open(self) -> None:
        app = web.Application()
        app.router.add_get("/", self._page)
        app.router.add_get("/ws", self._socket)
        for name in _STATIC[1:]:
            app.router.add_get(f"/{name}", self._page)
        app.router.add_get("/favicon.ico", self._no_icon)
        self._runner = web.AppRunner(app, access_log=None)
        await self._runner.setup()
        site = web.TCPSite(self._runner, self.host, self._port)
        await site.start()
        server: Any = site._server  # aiohttp keeps the bound socket there
        if server is not None and server.sockets:
            self._port = server.sockets[0].getsockname()[1]
        self._wake = asyncio.Event()

    async def _shutdown(self) -> None:
        for ws in list(self._clients.values()):
            await ws.close()
        if self._runner is not None:
            await self._runner.cleanup()
        if self._wake is not None:
            self._stopping = True
            self._wake.set()

    # -- from the robot's thread -----------------------------------------------------------

    def wants_sample(self) -> bool:
        """Whether a sample now would be sent (so that it is only made then)."""
        due = time.monotonic() - self._sent_sample >= 1.0 / SAMPLE_HZ
        return self.history.due() or (bool(self._clients) and due)

    def publish(self, sample: dict[str, Any], force: bool = False) -> None:
        """The newest sample; sent to the pages at most SAMPLE_HZ times a second (unless
        ``force``: a replay's seek must show where it landed)."""
        self.history.add(sample)
        now = time.monotonic()
        if not self._clients or (not force and now - self._sent_sample < 1.0 / SAMPLE_HZ):
            return
        self._sent_sample = now
        self._sample = sample  # encoded on the server's thread, not the robot's
        self._poke()

    def wants_image(self) -> bool:
        """Whether a camera frame now would be sent (so that it is only encoded then)."""
        return bool(self._clients) and time.monotonic() - self._sent_image >= 1.0 / IMAGE_HZ

    def publish_image(self, jpeg: bytes) -> None:
        """A camera frame already JPEG (a recording's)."""
        self._sent_image = time.monotonic()
        self._image = jpeg
        self._poke()

    def publish_frame(self, rgb: Any) -> None:
        """A camera frame, RGB888 (the caller's copy): JPEG-encoded on the server's thread."""
        self._sent_image = time.monotonic()
        self._frame = rgb
        self._poke()

    def broadcast_state(self) -> None:
        """Tell every page its role again (who holds control changed)."""
        self._poke()

    def _poke(self) -> None:
        loop, wake = self._loop, self._wake
        if loop is not None and wake is not None:
            with contextlib.suppress(RuntimeError):  # closing
                loop.call_soon_threadsafe(wake.set)

    # -- the event loop ----------------------------------------------------------------------

    async def _pump(self) -> None:
        """Send what was published to every page, newest only."""
        assert self._wake is not None
        while not self._stopping:
            await self._wake.wait()
            self._wake.clear()
            sample, self._sample = self._sample, None
            image, self._image = self._image, None
            frame, self._frame = self._frame, None
            text = json.dumps({"type": "sample", **sample}) if sample is not None else None
            if frame is not None:
                from ego.camera.encode import encode_jpeg  # loaded by the camera in use

                image = encode_jpeg(frame, JPEG_QUALITY)
            for client, ws in list(self._clients.items()):
                with contextlib.suppress(ConnectionError, RuntimeError):
                    if text is not None:
                        await ws.send_str(text)
                    if image is not None:
                        await ws.send_bytes(image)
                    await ws.send_json(self.feed.state(client))

    async def _no_icon(self, request: web.Request) -> web.StreamResponse:
        return web.Response(status=204)

    async def _page(self, request: web.Request) -> web.StreamResponse:
        if not token_matches(request.query.get("token"), self.token):
            return web.Response(status=403, text="this dashboard needs its token: open the "
                                "URL that ego printed (it ends in ?token=...)\n")  # fmt: skip
        name = request.path.strip("/") or "index.html"
        text = resources.files("ego.dashboard").joinpath("static").joinpath(name).read_text("utf-8")
        content_type = _TYPES[name[name.rindex(".") :]]
        return web.Response(text=text, content_type=content_type,
                            headers={"Cache-Control": "no-store"})  # fmt: skip

    async def _socket(self, request: web.Request) -> web.StreamResponse:
        if not token_matches(request.query.get("token"), self.token):
            return web.Response(status=403, text="wrong or missing token\n")
        if not same_origin(request.headers.get("Origin"), request.headers.get("Host")):
            return web.Response(status=403, text="a page of another site may not connect\n")
        ws = web.WebSocketResponse(heartbeat=5.0, max_msg_size=4096)
        await ws.prepare(request)
        client = next(self._ids)
        self._clients[client] = ws
        try:
            await ws.send_json({"type": "hello", **self.feed.hello()})
            await ws.send_str(self.history.message())
            await ws.send_json(self.feed.state(client))
            async for msg in ws:
                if msg.type != WSMsgType.TEXT:
                    continue
                try:
                    message = json.loads(msg.data)
                except ValueError:
                    message = None
                reply = self.feed.handle(client, message)
                if reply.stop_now:
                    await asyncio.get_running_loop().run_in_executor(None, self._stop_now)
                if reply.message is not None:
                    await ws.send_json(reply.message)
                self._poke()  # every page's state may have changed
        finally:
            del self._clients[client]
            self.feed.leave(client)
            self._poke()
        return ws

    def _stop_now(self) -> None:
        try:
            self.feed.stop_now()
        except Exception as exc:  # the robot is gone: the page is told by the samples
            log.error("dashboard stop could not reach the robot: %s", exc)
