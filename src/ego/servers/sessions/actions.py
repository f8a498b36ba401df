"""What ``ego serve``'s session hands its adapter: peers, actions, and its statistics.

Plain values without I/O, shared by :mod:`ego.servers.sessions.session` and
:mod:`ego.servers.sessions.gate`, and performed by :mod:`ego.servers.socket.server`.
"""

from __future__ import annotations

import collections
import logging
from collections.abc import Hashable
from dataclasses import dataclass, field

from ego.errors import EgoError
from ego.net.frames import Frame, FrameKey, MessageType, encode_frame
from ego.net.handshake import Hello
from ego.net.messages import RobotCall
from ego.net.payloads import error_fields, pack_error
from ego.net.sequence import SequenceGuard

__all__ = [
    "Action",
    "Authenticated",
    "ControllerState",
    "Hangup",
    "Peer",
    "PendingHandshake",
    "Run",
    "Send",
    "ServerStats",
    "StopRobot",
    "error_frame",
    "small_reply",
]


@dataclass(frozen=True, slots=True)
class Peer:
    """Where a frame came from and replies go: a TCP connection or a UDP address."""

    key: Hashable
    label: str
    host: str
    #: Replies bigger than this go out in PARTs; None for a stream (no limit).
    datagram: int | None = None


@dataclass(frozen=True, slots=True)
class Send:
    peer: Peer
    data: bytes
    #: Wait this long first (a wrong proof's answer, braking guesses).
    delay_s: float = 0.0


@dataclass(frozen=True, slots=True)
class Run:
    """Run ``call`` on the robot, then tell :meth:`Session.completed` how it went."""

    peer: Peer
    session: int
    seq: int
    call: RobotCall


@dataclass(frozen=True, slots=True)
class StopRobot:
    """Stop the wheels and LEDs now (and release the camera if the client opened it)."""

    reason: str
    close_camera: bool = False
    #: How loudly to log it (a goodbye is routine; a deadman is a warning).
    level: int = logging.WARNING


@dataclass(frozen=True, slots=True)
class Hangup:
    peer: Peer
    delay_s: float = 0.0


@dataclass(frozen=True, slots=True)
class Authenticated:
    """``peer`` controls the robot: its stream's frames must now be sealed with ``key``."""

    peer: Peer
    key: FrameKey | None


Action = Send | Run | StopRobot | Hangup | Authenticated


@dataclass(slots=True)
class ServerStats:
    """What the server did, for logs, tests and benchmarks."""

    requests: int = 0
    steps: int = 0
    #: Retransmitted requests answered from the cache, without running them again.
    repeats: int = 0
    #: Requests older than the last one (late duplicates, replays), ignored.
    stale: int = 0
    #: Frames that failed to decode (bad magic, CRC, size...).
    malformed: int = 0
    #: Frames of a sealed session whose MAC failed, or unsealed: forged or altered.
    forged: int = 0
    #: Handshakes refused (wrong secret, robot busy, wrong version).
    refused: int = 0
    #: UDP HELLOs answered with a cookie only (no state kept).
    cookies: int = 0
    sessions: int = 0
    #: Times the robot was stopped because its client went silent or away.
    deadman_stops: int = 0
    #: How long the controller had been silent, on the server's clock, each time the
    #: deadman fired (the deadline plus how late it fired).
    deadman_silences: list[float] = field(default_factory=list)
    #: Requests refused because another of the same session was still running.
    pipelined: int = 0
    #: Connections dropped unheard: over the half-open cap, never in control in time,
    #: or too slow to read what they asked for.
    dropped: int = 0
    errors: collections.Counter[str] = field(default_factory=collections.Counter)


@dataclass(slots=True)
class PendingHandshake:
    """A client between its HELLO and its AUTH."""

    peer: Peer
    id: int
    hello: Hello
    hello_payload: bytes
    server_nonce: bytes
    created: float
    guard: SequenceGuard = field(default_factory=SequenceGuard)


@dataclass(slots=True)
class ControllerState:
    """The client in control as the socket wire knows it: its session, key and dedup (when
    it was last heard and whether a call of it runs: its
    :class:`~ego.servers.sessions.control.ControlSession`)."""

    peer: Peer
    id: int
    key: FrameKey | None
    hello_payload: bytes
    guard: SequenceGuard = field(default_factory=SequenceGuard)
    #: The last reply too big for one datagram, for FETCH: (seq, type, payload).
    big: tuple[int, MessageType, bytes] | None = None
    camera_open: bool = False
    #: Requests it sent while another ran, refused (logged once a session).
    pipelined: int = 0


def error_frame(stats: ServerStats, frame: Frame, exc: EgoError) -> bytes:
    """An unsealed ERROR answering ``frame`` (to a peer that holds no session key)."""
    stats.errors[type(exc).__name__] += 1
    payload = pack_error(type(exc).__name__, str(exc), error_fields(exc))
    return encode_frame(MessageType.ERROR, frame.seq, payload, frame.session)


def small_reply(peer: Peer, data: bytes, size: int) -> list[Action]:
    """A reply to a peer not yet proven: over UDP never bigger than what asked for it, so
    that a forged source address cannot turn the server into an amplifier."""
    if peer.datagram is not None and len(data) > size:
        return []
    return [Send(peer, data)]
