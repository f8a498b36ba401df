"""``ego serve``: the asyncio adapter that performs the remote session over TCP and UDP.

All decisions live in the sans-I/O :class:`~ego.servers.sessions.session.Session`; this module
only moves bytes and runs calls:

* TCP connections and UDP datagrams are fed to the session, whose actions are carried
  out here: replies sent (a wrong proof's answer after its delay), robot calls run on
  the :class:`~ego.servers.service.RobotService` in a worker thread (one for the
  channel, one for the camera), connections hung up;
* until a TCP peer has authenticated, its frames may carry at most
  MAX_PREAUTH_PAYLOAD bytes, at most ``max_unauthenticated`` such connections are
  kept (the oldest goes first), and one that has not taken control within
  ``handshake_timeout_s`` is dropped; a reader too slow for its replies is dropped
  once ``write_limit`` bytes wait for it;
* the deadman is a :class:`~ego.nursery.DeadlineTimer` (a thread of its own), so that it
  fires on time even when the event loop is flooded: it sleeps until the session's next
  deadline (re-armed sooner by the events that bring one closer), and stops the robot
  itself;
* every task and thread has an owner that ends and joins it in :meth:`Server.aclose`:
  the tasks and the deadman's timer a :class:`~ego.nursery.Nursery` (a thread still
  alive then is a :class:`~ego.errors.ThreadLeakError`), the three worker threads the
  server (none is a daemon);
* a stop never waits behind calls: it runs in a thread of its own, and a call whose
  session ended before its turn came is dropped, not run (the session lets a
  controller have one request in flight, so at most one batch runs after it is gone);
* running out of file descriptors is logged once in a while, quietly.

Off loopback the server insists on a shared secret (:mod:`ego.net.handshake`).

>>> server = Server(link, listen="tcp://127.0.0.1:4242")   # doctest: +SKIP
>>> with ServerThread(server) as running:                   # doctest: +SKIP
...     print(running.urls)
"""

from __future__ import annotations

import asyncio
import concurrent.futures
import contextlib
import errno
import functools
import logging
import threading
import time
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Any

from ego.errors import FrameError
from ego.net.auth import FailureThrottle, coerce_secret, is_loopback
from ego.net.frames import (
    DEFAULT_CHUNK_SIZE,
    MAX_DATAGRAM,
    MAX_PREAUTH_PAYLOAD,
    SEALED_OVERHEAD,
    Frame,
    FrameReader,
)
from ego.net.urls import parse_url
from ego.nursery import DeadlineTimer, Nursery
from ego.seam.channel import Channel
from ego.servers.service import FrameEncoder, RobotService, encode_image
from ego.servers.sessions.actions import Action, Authenticated, Hangup, Peer, Run, Send, StopRobot
from ego.servers.sessions.session import Session
from ego.servers.socket.peers import MAX_UNAUTHENTICATED, WRITE_LIMIT, Peers, owner_only

if TYPE_CHECKING:
    from ego.camera.source import FrameSource

__all__ = [
    "DEFAULT_DEADLINE_S",
    "DEFAULT_LISTEN",
    "MAX_UNAUTHENTICATED",
    "Server",
    "check_listen",
]

log = logging.getLogger(__name__)

DEFAULT_LISTEN = "tcp://127.0.0.1:4242"
#: How long the controlling client may stay silent before the robot is stopped.
DEFAULT_DEADLINE_S = 0.5


def check_listen(
    listen: Sequence[str], secret: bytes | None, require_secret: bool = False
) -> list[tuple[str, str, int]]:
    """The (scheme, host, port) of each listen URL; ValueError for a bad URL, or for an
    address off loopback (or ``require_secret``) without a shared secret."""
    if not listen:
        raise ValueError("nothing to listen on")
    endpoints = [parse_url(url) for url in listen]
    off_loopback = [f"{s}://{h}:{p}" for s, h, p in endpoints if s != "unix" and not is_loopback(h)]
    if secret is None and (require_secret or off_loopback):
        where = ", ".join(off_loopback) or "this server"
        raise ValueError(
            f"{where} is reachable from other machines: give a shared secret "
            "(ego serve --secret-file FILE) or listen on 127.0.0.1"
        )
    return endpoints


class Server:
    """Serves one robot's channel (and camera) to one controlling client at a time.

    ``listen`` is one or more ``tcp://HOST:PORT`` / ``udp://HOST:PORT`` (port 0 picks a
    free port; :attr:`urls` tells which). ``secret`` is the shared secret; it is required
    when listening off loopback or when ``require_secret`` is true. The server does not
    own ``channel``: whoever opened it closes it after :meth:`aclose`.
    """

    def __init__(
        self,
        channel: Channel,
        *,
        listen: str | Sequence[str] = DEFAULT_LISTEN,
        secret: str | bytes | None = None,
        require_secret: bool = False,
        deadline_s: float = DEFAULT_DEADLINE_S,
        frame_source: FrameSource | None = None,
        frame_encoder: FrameEncoder = encode_image,
        chunk_size: int = DEFAULT_CHUNK_SIZE,
        handshake_timeout_s: float = 2.0,
        auth_failure_delay_s: float = 0.2,
        max_unauthenticated: int = MAX_UNAUTHENTICATED,
        write_limit: int = WRITE_LIMIT,
    ) -> None:
        self.channel = channel
        self.listen = [listen] if isinstance(listen, str) else list(listen)
        secret_bytes = coerce_secret(secret)
        self._endpoints = check_listen(self.listen, secret_bytes, require_secret)
        _check_limits(deadline_s, chunk_size)
        self.chunk_size = chunk_size
        self.handshake_timeout_s = handshake_timeout_s
        self.service = RobotService(channel, frame_source, frame_encoder)
        self.session = Session(
            secret=secret_bytes,
            deadline_s=deadline_s,
            chunk_size=chunk_size,
            welcome=self.service.welcome,
            handshake_timeout_s=handshake_timeout_s,
            throttle=FailureThrottle(base_s=auth_failure_delay_s),
        )
        self.stats = self.session.stats
        self.urls: list[str] = []
        #: The session is fed from the loop and from the deadman thread.
        self._lock = threading.Lock()
        self.peers = Peers(self.stats, max_unauthenticated, write_limit)
        self._closers: list[Callable[[], None]] = []
        self._tasks = Nursery("ego serve")
        self._loop: asyncio.AbstractEventLoop | None = None
        #: The deadman: a timer asleep until the controller's deadline (set by start()).
        self.deadman: DeadlineTimer | None = None
        self._stopping = threading.Event()
        self._closed = asyncio.Event()
        self._last_fd_warning = 0.0
        self._channel_thread = concurrent.futures.ThreadPoolExecutor(1, "ego-serve-channel")
        self._camera_thread = concurrent.futures.ThreadPoolExecutor(1, "ego-serve-camera")
        #: Stops never queue behind calls (the channel's lock orders them with a batch).
        self._stop_thread = concurrent.futures.ThreadPoolExecutor(1, "ego-serve-stop")
        #: The last stop handed to it: replies wait for it (a repeated BYE is told OK once
        #: the robot stands still, as the first one is).
        self._stop_running: asyncio.Future[None] | None = None

    @property
    def deadline_s(self) -> float:
        return self.session.deadline_s

    @property
    def auth_required(self) -> bool:
        return self.session.secret is not None

    @property
    def controller(self) -> str | None:
        """Who controls the robot now ("tcp 127.0.0.1:50312"), or None."""
        peer = self.session.controller
        return peer.label if peer else None

    # -- lifecycle -------------------------------------------------------------------------

    async def start(self) -> None:
        """Bind every listen address and start the deadman thread."""
        loop = self._loop = asyncio.get_running_loop()
        loop.set_exception_handler(self._loop_error)
        for scheme, host, port in self._endpoints:
            await _bind(self, loop, scheme, host, port)
        self.deadman = self._tasks.start_timer(self._deadline_passed, name="ego-serve-deadman")
        with self._lock:
            self._arm(self.session.next_deadline())
        log.info(
            "serving %s (%s firmware) on %s%s",
            self.channel.name,
            self.channel.profile.firmware,
            ", ".join(self.urls),
            " (shared secret required)" if self.auth_required else "",
        )

    async def serve_forever(self) -> None:
        """Serve until :meth:`aclose` (start first if not started)."""
        if not self.urls:
            await self.start()
        await self._closed.wait()

    async def aclose(self) -> None:
        """Stop the robot if someone controls it, then stop listening; idempotent."""
        if self._stopping.is_set():
            return
        self._stopping.set()
        with self._lock:
            actions = self.session.shutdown()
        await self._perform(actions)
        for close in self._closers:
            close()
        try:
            await self._tasks.aclose()  # the deadman's timer too
        finally:
            self._channel_thread.shutdown(wait=True)
            self._camera_thread.shutdown(wait=True)
            self._stop_thread.shutdown(wait=True)
            self._closed.set()

    # -- input -------------------------------------------------------------------------------

    def feed(self, actions: list[Action]) -> None:
        """Carry out ``actions`` (in order) from the loop thread."""
        if actions:
            self._tasks.start_soon(self._perform(actions))

    def call_session(self, method: Callable[..., list[Action]], *args: Any) -> None:
        with self._lock:
            actions = method(*args)
            due = self.session.next_deadline()
        self._arm(due)
        self.feed(actions)

    def _arm(self, due: float | None) -> None:
        """Wake the deadman by ``due`` (a no-op unless it brings its deadline closer)."""
        if due is not None and self.deadman is not None:
            self.deadman.arm(due)

    # -- output ------------------------------------------------------------------------------

    async def _perform(self, actions: list[Action]) -> None:
        loop = asyncio.get_running_loop()
        for action in actions:
            try:
                if isinstance(action, Send):
                    if self._stop_running is not None:  # no reply while a stop runs
                        await asyncio.shield(self._stop_running)
                    self._send_later(action.peer, action.data, action.delay_s)
                elif isinstance(action, Hangup):
                    loop.call_later(action.delay_s, self.peers.hang_up, action.peer)
                elif isinstance(action, Authenticated):
                    self.peers.authenticated(action.peer, action.key)
                elif isinstance(action, Run):
                    self.feed_run(action)
                else:
                    stop = loop.run_in_executor(self._stop_thread, self._stop_robot, action)
                    self._stop_running = stop
                    await stop
            except Exception:  # one bad action must never take the server down
                log.exception("internal error performing %s", type(action).__name__)

    def feed_run(self, run: Run) -> None:
        self._tasks.start_soon(self._run(run))

    async def _run(self, run: Run) -> None:
        pool = self._camera_thread if self.service.uses_camera(run.call) else self._channel_thread
        result: bytes | Exception | None
        try:
            result = await asyncio.get_running_loop().run_in_executor(
                pool, self.service.run, run.call, functools.partial(self._live, run.session)
            )
        except Exception as exc:
            if not isinstance(exc, FrameError):
                log.warning("%s: %s failed: %s", run.peer.label, type(run.call).__name__, exc)
            result = exc
        if result is None:
            log.debug("%s: %s dropped, its session ended", run.peer.label, type(run.call).__name__)
            return
        self.call_session(self.session.completed, run.session, run.seq, result, time.monotonic())

    def _live(self, session: int) -> bool:
        with self._lock:
            return self.session.live(session)

    def _stop_robot(self, stop: StopRobot) -> None:
        try:
            self.service.stop(stop.close_camera)
            log.log(stop.level, "%s: motors stopped, LEDs off", stop.reason)
        except Exception as exc:
            log.error("%s, and stopping the robot failed: %s", stop.reason, exc)

    def _send_later(self, peer: Peer, data: bytes, delay_s: float) -> None:
        if delay_s > 0:
            assert self._loop is not None
            self._loop.call_later(delay_s, self.peers.send, peer, data)
        else:
            self.peers.send(peer, data)

    def stream_opened(self, peer: Peer, transport: asyncio.Transport, reader: FrameReader) -> None:
        self.peers.opened(peer, transport, reader)
        assert self._loop is not None
        self._loop.call_later(self.handshake_timeout_s, self._expire, peer)

    def _expire(self, peer: Peer) -> None:
        """A connection that has not taken control in time is dropped (slowloris)."""
        if not self.session.controls(peer):
            self.peers.drop(peer)

    def stream_closed(self, peer: Peer) -> None:
        self.peers.closed(peer)
        self.call_session(self.session.peer_lost, peer)

    # -- the deadman and the loop's own errors ---------------------------------------------------

    def _deadline_passed(self, now: float) -> float | None:
        """The deadman, on its timer's thread (on time whatever the event loop is doing):
        the session's tick, the stop carried out here, not behind the loop's backlog; the
        next deadline."""
        with self._lock:
            actions = self.session.tick(now)
            following = self.session.next_deadline()
        for action in actions:
            if isinstance(action, StopRobot):
                self._stop_robot(action)
        rest: list[Action] = [a for a in actions if not isinstance(a, StopRobot)]
        loop = self._loop
        if rest and loop is not None and not loop.is_closed():
            with contextlib.suppress(RuntimeError):  # the loop ended meanwhile
                loop.call_soon_threadsafe(self.feed, rest)
        return following

    def _loop_error(self, loop: asyncio.AbstractEventLoop, context: dict[str, Any]) -> None:
        exc = context.get("exception")
        if isinstance(exc, OSError) and exc.errno in (errno.EMFILE, errno.ENFILE):
            # Out of file descriptors: asyncio pauses accepting for a second by itself.
            now = time.monotonic()
            if now - self._last_fd_warning > 10:
                self._last_fd_warning = now
                log.warning("out of file descriptors: new connections wait (%s)", exc)
            return
        loop.default_exception_handler(context)


async def _bind(
    server: Server, loop: asyncio.AbstractEventLoop, scheme: str, host: str, port: int
) -> None:
    """Listen on one endpoint of ``server``: its closer and its URL (the port it got)."""
    if scheme == "unix":
        # Only this user may connect: the socket is created with mode 600.
        with owner_only():
            unix = await loop.create_unix_server(lambda: _TcpProtocol(server), host)
        server._closers.append(unix.close)
        server.urls.append(f"unix://{host}")
        return
    if scheme == "tcp":
        tcp = await loop.create_server(lambda: _TcpProtocol(server), host, port)
        sockname = tcp.sockets[0].getsockname()
        server._closers.append(tcp.close)
    else:
        index = len(server.peers.datagrams)
        transport, _ = await loop.create_datagram_endpoint(
            lambda: _UdpProtocol(server, index), local_addr=(host, port)
        )
        server.peers.datagrams.append(transport)
        sockname = transport.get_extra_info("sockname")
        server._closers.append(transport.close)
    shown = f"[{sockname[0]}]" if ":" in sockname[0] else sockname[0]
    server.urls.append(f"{scheme}://{shown}:{sockname[1]}")


def _receive_each(session: Session, peer: Peer, frames: list[Frame], now: float) -> list[Action]:
    """What the session makes of the frames one read of a stream completed, in order."""
    return [action for frame in frames for action in session.receive(peer, frame, now)]


def _check_limits(deadline_s: float, chunk_size: int) -> None:
    if not 0 < deadline_s <= 60:
        raise ValueError(f"deadline {deadline_s} s is outside 0..60 s")
    if not SEALED_OVERHEAD + 1024 <= chunk_size <= MAX_DATAGRAM:
        raise ValueError(
            f"chunk size {chunk_size} is outside {SEALED_OVERHEAD + 1024}..{MAX_DATAGRAM}"
        )


class _TcpProtocol(asyncio.Protocol):
    def __init__(self, server: Server) -> None:
        self.server = server
        self.reader = FrameReader(MAX_PREAUTH_PAYLOAD)
        self.peer: Peer | None = None

    def connection_made(self, transport: asyncio.BaseTransport) -> None:
        assert isinstance(transport, asyncio.Transport)
        addr = transport.get_extra_info("peername")
        if isinstance(addr, tuple):
            label, host = f"tcp {addr[0]}:{addr[1]}", str(addr[0])
        else:  # a Unix socket: a process of this user on this machine
            label, host = f"unix {transport.get_extra_info('sockname')}", "localhost"
        self.peer = Peer(("tcp", id(transport), None), label, host)
        self.server.stream_opened(self.peer, transport, self.reader)

    def data_received(self, data: bytes) -> None:
        assert self.peer is not None
        server, peer = self.server, self.peer
        server.peers.heard(peer)
        try:
            frames = self.reader.feed(data)
        except FrameError as exc:
            server.call_session(server.session.stream_error, peer, exc)
            return
        # In one go: a pipelined burst costs one task, and the close behind it is read
        # that much sooner.
        server.call_session(_receive_each, server.session, peer, frames, time.monotonic())

    def connection_lost(self, exc: Exception | None) -> None:
        if self.peer is not None:
            self.server.stream_closed(self.peer)


class _UdpProtocol(asyncio.DatagramProtocol):
    def __init__(self, server: Server, index: int) -> None:
        self.server = server
        self.index = index

    def datagram_received(self, data: bytes, addr: Any) -> None:
        server = self.server
        peer = Peer(("udp", self.index, addr), f"udp {addr[0]}:{addr[1]}", str(addr[0]),
                    server.chunk_size)  # fmt: skip
        server.call_session(server.session.datagram, peer, data, time.monotonic())

    def error_received(self, exc: Exception) -> None:
        log.debug("UDP error (a client went away?): %s", exc)
