"""The limits ego serve puts on connections: slow readers, strangers beyond the cap."""

from __future__ import annotations

from ego.net.frames import FrameReader
from ego.servers.sessions.actions import Peer, ServerStats
from ego.servers.socket.peers import PREAUTH_WRITE_LIMIT, Peers


class Stream:
    """An asyncio transport whose peer never reads: what is written stays buffered."""

    def __init__(self) -> None:
        self.buffered = 0
        self.aborted = False

    def write(self, data: bytes) -> None:
        self.buffered += len(data)

    def get_write_buffer_size(self) -> int:
        return self.buffered

    def is_closing(self) -> bool:
        return self.aborted

    def abort(self) -> None:
        self.aborted = True

    def close(self) -> None:
        self.aborted = True


def _peer(n: int) -> Peer:
    return Peer(("tcp", n, None), f"tcp peer {n}", "127.0.0.1")


def test_a_stranger_that_never_reads_is_dropped_after_64_kib() -> None:
    stats = ServerStats()
    peers = Peers(stats, max_unauthenticated=64, write_limit=4 << 20)
    stream, peer = Stream(), _peer(1)
    peers.opened(peer, stream, FrameReader())  # type: ignore[arg-type]
    sent = 0
    while not stream.aborted:
        peers.send(peer, bytes(250))
        sent += 250
    assert PREAUTH_WRITE_LIMIT < sent <= PREAUTH_WRITE_LIMIT + 250
    assert stats.dropped == 1


def test_the_controller_may_have_megabytes_waiting_but_not_more() -> None:
    stats = ServerStats()
    peers = Peers(stats, max_unauthenticated=64, write_limit=4 << 20)
    stream, peer = Stream(), _peer(1)
    peers.opened(peer, stream, FrameReader())  # type: ignore[arg-type]
    peers.authenticated(peer, None)
    for _ in range(4):
        peers.send(peer, bytes(1 << 20))
    assert not stream.aborted
    peers.send(peer, bytes(1))
    assert stream.aborted and stats.dropped == 1


def test_over_the_cap_a_silent_connection_goes_before_one_that_spoke() -> None:
    stats = ServerStats()
    peers = Peers(stats, max_unauthenticated=4, write_limit=4 << 20)
    streams = [Stream() for _ in range(5)]
    for n in range(4):
        peers.opened(_peer(n), streams[n], FrameReader())  # type: ignore[arg-type]
    peers.heard(_peer(0))  # the oldest started a handshake
    peers.opened(_peer(4), streams[4], FrameReader())  # type: ignore[arg-type]
    assert [s.aborted for s in streams] == [False, True, False, False, False]
