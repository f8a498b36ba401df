"""The dashboard's web server: the page, and a WebSocket per browser, on a thread of its own.

aiohttp serves both (one maintained asyncio library for HTTP and WebSockets, which the
rest of ego's asyncio code already fits). The server knows nothing of robots: a
:class:`Feed` gives it the first message a page gets, handles the pages' commands, and
pushes samples and camera frames through :meth:`DashboardServer.publish` and
:meth:`DashboardServer.publish_image`, from any thread. Pages get at most
:data:`SAMPLE_HZ` samples and :data:`IMAGE_HZ` frames a second, the newest ones: a
slow browser skips frames, it never slows the robot. Who gets in is
:mod:`~ego.servers.dashboard.access`'s and :mod:`~ego.servers.dashboard.pages`' business; the server
caps the pages at :data:`MAX_PAGES` and a command at :data:`MAX_MESSAGE_BYTES`.
"""

from __future__ import annotations

import asyncio
import contextlib
import itertools
import json
import logging
import threading
import time
from typing import Any, Protocol

from aiohttp import WSMsgType, web

from ego.nursery import Nursery
from ego.servers.dashboard.access import Gate, url_host
from ego.servers.dashboard.control import Reply
from ego.servers.dashboard.history import History
from ego.servers.dashboard.pages import make_app, refuse

__all__ = ["IMAGE_HZ", "JPEG_QUALITY", "MAX_MESSAGE_BYTES", "MAX_PAGES", "SAMPLE_HZ",
           "DashboardServer", "Feed"]  # fmt: skip

log = logging.getLogger(__name__)

SAMPLE_HZ = 25
IMAGE_HZ = 10
JPEG_QUALITY = 80
#: How many pages may be open at once: a lab's worth of viewers, not a flood.
MAX_PAGES = 20
#: The longest command a page may send (a command is a small flat JSON object).
MAX_MESSAGE_BYTES = 4096
_NOT_A_COMMAND = (f"a command is one JSON object of at most {MAX_MESSAGE_BYTES} bytes, "
                  "not nested deeply")  # fmt: skip


class Feed(Protocol):
    """What the server shows and obeys: a live robot, or a recording played back."""

    def hello(self) -> dict[str, Any]: ...

    def state(self, client: object) -> dict[str, Any]: ...

    def handle(self, client: object, message: object) -> Reply: ...

    def leave(self, client: object) -> None: ...

    def stop_now(self) -> None: ...


class DashboardServer:
    """Serves ``feed`` at http://HOST:PORT/ until closed (``port`` 0: any free port).

    Off loopback it needs ``secret`` (its token derives from it); ``names`` are more host
    names the page may be opened by (besides loopback's and ``host``)."""

    def __init__(
        self, feed: Feed, host: str = "127.0.0.1", port: int = 8765,
        secret: bytes | None = None, names: tuple[str, ...] = (),
    ) -> None:  # fmt: skip
        self.gate = Gate(host, secret, names)
        self.feed = feed
        self.host = host
        self.token = self.gate.token
        self._port = port
        self._clients: dict[int, web.WebSocketResponse] = {}
        self._admitted = 0
        self._ids = itertools.count(1)
        self._sample: dict[str, Any] | None = None
        self._image: bytes | None = None
        self._frame: Any = None
        self._sent_sample = self._sent_image = 0.0
        self._loop: asyncio.AbstractEventLoop | None = None
        self._runner: web.AppRunner | None = None
        self._thread: threading.Thread | None = None
        #: Its thread's owner (a program that exits with the dashboard open closes it).
        self._threads = Nursery("the dashboard", at_exit=self.close)
        self._ready = threading.Event()
        self._failure: BaseException | None = None
        self._wake: asyncio.Event | None = None
        self._stopping = False
        #: The last minute of samples, sent to each page as it connects.
        self.history = History()

    # -- life --------------------------------------------------------------------------------

    def start(self) -> DashboardServer:
        """Start serving; raises OSError at once when the address cannot be bound."""
        self._thread = self._threads.start_thread(self._serve, name="ego-dashboard")
        self._ready.wait(10)
        if self._failure is not None:
            raise self._failure
        return self

    @property
    def port(self) -> int:
        return self._port

    @property
    def url(self) -> str:
        """The URL that logs a browser in (bound to every interface: this machine's name)."""
        return f"http://{url_host(self.host)}:{self._port}/?token={self.token}"

    @property
    def client_count(self) -> int:
        return len(self._clients)

    def close(self) -> None:
        """Stop serving and join the thread (:class:`~ego.errors.ThreadLeakError` if it is
        still running 5 s later); idempotent."""
        loop, thread = self._loop, self._thread
        if loop is None or thread is None:
            return
        with contextlib.suppress(RuntimeError):  # the loop already ended
            asyncio.run_coroutine_threadsafe(self._shutdown(), loop).result(5)
        self._threads.close()
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
        app = make_app(self.gate, self._socket)
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

    async def _socket(self, request: web.Request) -> web.StreamResponse:
        if not self.gate.admits(request.cookies, request.query.get("token")):
            return refuse(403, "this dashboard's socket needs its login cookie (open the URL "
                          "that ego printed) or ?token=...")  # fmt: skip
        if not self.gate.origin_ok(request.headers.get("Origin"), request.headers.get("Host")):
            return refuse(403, "a page of another site may not connect")
        if self._admitted >= MAX_PAGES:
            return refuse(503, f"this dashboard already serves {MAX_PAGES} pages: close one")
        self._admitted += 1  # before the first await: the cap holds under a flood
        try:
            return await self._converse(request)
        finally:
            self._admitted -= 1

    async def _converse(self, request: web.Request) -> web.WebSocketResponse:
        ws = web.WebSocketResponse(heartbeat=5.0, max_msg_size=MAX_MESSAGE_BYTES)
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
                except (ValueError, RecursionError):  # RecursionError: nested too deep
                    await ws.send_json({"type": "error", "error": _NOT_A_COMMAND})
                    continue
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
