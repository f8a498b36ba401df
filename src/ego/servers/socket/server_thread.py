"""A :class:`~ego.servers.socket.server.Server` on its own event loop in a thread its
nursery owns: for tests, benchmarks and a PC beside an emulator (``ego serve`` runs the
loop in the main thread instead)."""

from __future__ import annotations

import asyncio
import contextlib
import threading
from types import TracebackType

from ego.nursery import Nursery
from ego.servers.socket.server import Server

__all__ = ["ServerThread"]


class ServerThread:
    """A :class:`Server` on its own event loop in a background thread.

    For tests, benchmarks and a PC beside an emulator; ``ego serve`` runs the loop in
    the main thread instead. :meth:`stop` waits up to ``join_s`` for the thread; one still
    running then is a :class:`~ego.errors.ThreadLeakError` (and a later stop waits again).
    """

    def __init__(self, server: Server, join_s: float = 10.0) -> None:
        self.server = server
        self._loop: asyncio.AbstractEventLoop | None = None
        self._nursery = Nursery("ego serve's thread", join_s)
        self._ready = threading.Event()
        self._error: BaseException | None = None
        #: What the server's close raised (a thread of its own left running, say).
        self._close_error: BaseException | None = None
        self._stop: asyncio.Event | None = None

    @property
    def urls(self) -> list[str]:
        return self.server.urls

    @property
    def url(self) -> str:
        return self.server.urls[0]

    def start(self) -> ServerThread:
        self._nursery.start_thread(self._run, name="ego-serve")
        self._ready.wait()
        if self._error is not None:
            raise self._error
        return self

    def _run(self) -> None:
        try:
            asyncio.run(self._main())
        except Exception as exc:  # stop() raises it in its caller's thread
            self._close_error = exc
        finally:
            self._ready.set()  # a start() waiting on a thread that failed early

    async def _main(self) -> None:
        self._loop = asyncio.get_running_loop()
        self._stop = asyncio.Event()
        try:
            await self.server.start()
        except BaseException as exc:
            self._error = exc
            self._ready.set()
            await self.server.aclose()
            return
        self._ready.set()
        await self._stop.wait()
        await self.server.aclose()

    def stop(self) -> None:
        """Stop the server (the robot is stopped if a client controls it); idempotent."""
        loop, stop, self._loop = self._loop, self._stop, None
        if loop is not None and stop is not None:
            with contextlib.suppress(RuntimeError):  # the loop already ended
                loop.call_soon_threadsafe(stop.set)
        self._nursery.close()
        failure, self._close_error = self._close_error, None
        if failure is not None:
            raise failure

    def __enter__(self) -> ServerThread:
        return self.start()

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        self.stop()
