"""The connections ``ego serve`` holds: where each peer's replies go, and the limits on
strangers (how many may wait, how much may queue for them, how big their frames may be)."""

from __future__ import annotations

import asyncio
import collections
import contextlib
import logging
import os
from collections.abc import Hashable, Iterator
from typing import Any, cast

from ego.net.frames import MAX_PAYLOAD, FrameKey, FrameReader
from ego.servers.sessions.actions import Peer, ServerStats

__all__ = ["MAX_UNAUTHENTICATED", "PREAUTH_WRITE_LIMIT", "WRITE_LIMIT", "Peers", "owner_only"]

log = logging.getLogger(__name__)

#: Half-open TCP connections kept at once: far more than honest clients (one controller,
#: a few refused), far fewer than the 1024 file descriptors a process usually has.
MAX_UNAUTHENTICATED = 64
#: Reply bytes that may wait for a slow reader (a few camera frames) before it is dropped.
WRITE_LIMIT = 4 * MAX_PAYLOAD
#: The same for a connection that has not authenticated: its replies are a few hundred
#: bytes each, so a peer that asks without reading is cut off early.
PREAUTH_WRITE_LIMIT = 64 * 1024


class Peers:
    """Stream connections by peer key (the half-open ones oldest first) and the datagram
    endpoints, and sending to any of them."""

    def __init__(self, stats: ServerStats, max_unauthenticated: int, write_limit: int) -> None:
        self.stats = stats
        # Never more than a quarter of the file descriptors the process may open: the
        # rest stay free for the controller's connection, the serial port, the camera.
        self.max_unauthenticated = min(max_unauthenticated, max(4, fd_limit() // 4))
        self.write_limit = write_limit
        self.datagrams: list[asyncio.DatagramTransport] = []
        self.streams: dict[Hashable, asyncio.Transport] = {}
        self.half_open: collections.OrderedDict[Hashable, asyncio.Transport] = (
            collections.OrderedDict()
        )
        self._readers: dict[Hashable, FrameReader] = {}
        #: The half-open connections that have not sent a byte yet, oldest first.
        self._silent: collections.OrderedDict[Hashable, None] = collections.OrderedDict()

    def opened(self, peer: Peer, transport: asyncio.Transport, reader: FrameReader) -> None:
        if len(self.half_open) >= self.max_unauthenticated:
            # More half-open connections than any real client needs: one goes, quietly,
            # the oldest of those that never said a word if there are any (a socket
            # flood), else the oldest. A client's handshake, a millisecond long, speaks
            # at once, so a flood of idle sockets never pushes it out.
            key = next(iter(self._silent)) if self._silent else next(iter(self.half_open))
            oldest = self.half_open.pop(key)
            self._silent.pop(key, None)
            self.stats.dropped += 1
            oldest.abort()
        self.streams[peer.key] = transport
        self._readers[peer.key] = reader
        self.half_open[peer.key] = transport
        self._silent[peer.key] = None

    def heard(self, peer: Peer) -> None:
        """``peer`` sent its first bytes: no longer first in line to be dropped."""
        self._silent.pop(peer.key, None)

    def authenticated(self, peer: Peer, key: FrameKey | None) -> None:
        """``peer`` controls the robot: never dropped as half-open, its frames sealed."""
        self.half_open.pop(peer.key, None)
        self._silent.pop(peer.key, None)
        reader = self._readers.get(peer.key)
        if reader is not None:
            reader.key = key
            reader.max_payload = MAX_PAYLOAD

    def drop(self, peer: Peer) -> None:
        transport = self.streams.get(peer.key)
        if transport is not None:
            self.stats.dropped += 1
            transport.abort()

    def closed(self, peer: Peer) -> None:
        self.streams.pop(peer.key, None)
        self._readers.pop(peer.key, None)
        self.half_open.pop(peer.key, None)
        self._silent.pop(peer.key, None)

    def send(self, peer: Peer, data: bytes) -> None:
        kind, where, address = cast(tuple[str, Any, Any], peer.key)
        if kind == "udp":
            endpoint = self.datagrams[where]
            if not endpoint.is_closing():
                endpoint.sendto(data, address)
            return
        stream = self.streams.get(peer.key)
        if stream is None or stream.is_closing():
            return
        stream.write(data)
        limit = PREAUTH_WRITE_LIMIT if peer.key in self.half_open else self.write_limit
        if stream.get_write_buffer_size() > limit:
            log.warning("%s reads too slowly: dropped", peer.label)
            self.stats.dropped += 1
            stream.abort()

    def hang_up(self, peer: Peer) -> None:
        stream = self.streams.get(peer.key)
        if stream is not None:
            stream.close()


def fd_limit() -> int:
    """How many files this process may have open (1024 when it cannot tell)."""
    try:
        import resource

        soft, _ = resource.getrlimit(resource.RLIMIT_NOFILE)
    except (ImportError, OSError, ValueError):
        return 1024
    return soft if soft > 0 else 1024


@contextlib.contextmanager
def owner_only() -> Iterator[None]:
    """Files (a Unix socket) created meanwhile get mode 600: only this user reaches them."""
    old = os.umask(0o177)
    try:
        yield
    finally:
        os.umask(old)
