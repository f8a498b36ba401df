"""``ego serve``'s conversation with its clients as a state machine, without I/O (as h11).

:class:`Session` is fed what arrives (a frame from a peer, a datagram, a finished robot
call, a lost connection, the passing of time) and returns what to do as
:data:`Action` values: send these bytes to that peer, run this call on the robot, stop
the robot, hang up. A thin asyncio adapter (:mod:`ego.servers.socket.server`) performs them over
TCP and UDP; the tests drive the session directly, with a fake clock.

Its parts:

* the handshake (:mod:`ego.net.handshake`): stateless UDP cookies, the server's proof,
  the client's proof checked in constant time, failures answered one at a time and
  later for a guessing host (:class:`~ego.net.auth.FailureThrottle`), the session
  key that seals every later frame;
* dedup (:class:`~ego.net.sequence.SequenceGuard`): a repeated request is answered from
  the cache and never runs twice; an older one is ignored;
* the lease, the deadman and one request in flight: the
  :class:`~ego.servers.sessions.control.ControlSession` the Zenoh node runs too, held
  by the session id: once the controller has been silent for ``deadline_s`` (nothing
  new, not even a heartbeat; repeats and stale frames do not count) the robot is
  stopped; a request that comes while another of its runs is refused, never queued,
  so that nothing it stacked up outlives it; a Run of a session that ended meanwhile
  is dropped by the adapter (:meth:`Session.live`);
* no amplification: a peer that has not proven its address (a UDP stranger, a forged
  source) is never answered with more bytes than it sent
  (:func:`~ego.servers.sessions.actions.small_reply`);
* the dispatch: a request is parsed once into a typed call (:mod:`ego.net.messages`)
  and handed to the adapter to run, or answered here (FETCH of a big reply's slices).
"""

from __future__ import annotations

import logging
from collections.abc import Callable

from ego.errors import FrameError, RemoteError, VersionMismatchError
from ego.net.auth import FailureThrottle
from ego.net.frames import (
    MAX_PAYLOAD,
    REQUEST_TYPES,
    Frame,
    FrameKey,
    MessageType,
    decode_frame,
    encode_frame,
    peek_session,
)
from ego.net.messages import Bye, Fetch, parse_request
from ego.net.sequence import Verdict
from ego.servers.sessions.actions import (
    Action,
    ControllerState,
    Hangup,
    Peer,
    Run,
    Send,
    ServerStats,
    StopRobot,
    error_frame,
    small_reply,
)
from ego.servers.sessions.control import ControlSession
from ego.servers.sessions.ended import MAX_EXPIRED, EndedSessions, ended_payload
from ego.servers.sessions.gate import Gate
from ego.servers.sessions.replies import (
    answer,
    count_bad,
    error_payload,
    fetch,
    malformed,
    reply_frame,
)

__all__ = ["MAX_EXPIRED", "Session", "error_payload"]  # MAX_EXPIRED: from sessions.ended

log = logging.getLogger(__name__)

#: What a controller may send while one of its requests runs: neither runs on the robot.
_WHILE_BUSY = frozenset({MessageType.FETCH, MessageType.BYE})


class Session:
    """The server's side of every client at once: one controls the robot, others wait.

    ``welcome`` gives what the server tells its client of the robot (firmware...);
    ``udp_cookies`` makes UDP clients prove their address before any state is kept.
    """

    def __init__(
        self,
        *,
        secret: bytes | None,
        deadline_s: float,
        chunk_size: int,
        welcome: Callable[[], dict[str, object]],
        handshake_timeout_s: float = 2.0,
        throttle: FailureThrottle | None = None,
        udp_cookies: bool = True,
    ) -> None:
        self.secret = secret
        self.chunk_size = chunk_size
        self.stats = ServerStats()
        #: The lease, the deadman, one request in flight: held by the session id.
        self.control: ControlSession[int] = ControlSession(deadline_s)
        self._controller: ControllerState | None = None
        self.ended = EndedSessions(self.stats)
        self.gate = Gate(
            self.stats,
            secret=secret,
            welcome=lambda: {**welcome(), "deadline_s": deadline_s, "chunk_size": chunk_size},
            handshake_timeout_s=handshake_timeout_s,
            throttle=throttle or FailureThrottle(),
            udp_cookies=udp_cookies,
            taken=self._taken,
        )

    # -- what the adapter asks -------------------------------------------------------------

    @property
    def deadline_s(self) -> float:
        return self.control.deadline_s

    @property
    def controller(self) -> Peer | None:
        return self._controller.peer if self._controller else None

    def controls(self, peer: Peer) -> bool:
        return self._controller is not None and self._controller.peer.key == peer.key

    def live(self, session: int) -> bool:
        """Whether ``session`` still controls the robot: a Run of one that ended is dropped."""
        return self.control.holds(session)

    def key_for(self, session: int | None) -> FrameKey | None:
        """The key that frames of ``session`` must be sealed with (None: unsealed)."""
        owner = self._controller
        return owner.key if owner is not None and owner.id == session else None

    # -- input -------------------------------------------------------------------------------

    def datagram(self, peer: Peer, data: bytes, now: float) -> list[Action]:
        """One UDP datagram: decoded with its session's key, then as :meth:`receive`."""
        key = self.key_for(peek_session(data))
        try:
            frame = decode_frame(data, key)
        except VersionMismatchError as exc:
            return small_reply(peer, malformed(self.stats, exc), len(data))
        except FrameError as exc:
            # Garbage gets no answer over UDP: a corrupted datagram is sent again by its
            # sender, and answering forged ones would make the server an amplifier.
            count_bad(self.stats, peer, exc, sealed=key is not None)
            return []
        return self.receive(peer, frame, now, len(data))

    def stream_error(self, peer: Peer, exc: FrameError) -> list[Action]:
        """A TCP stream that cannot be read on: say why (unless forged), hang up."""
        owner = self._controller
        forged = owner is not None and owner.peer.key == peer.key and owner.key is not None
        count_bad(self.stats, peer, exc, sealed=forged)
        actions: list[Action] = [] if forged else [Send(peer, malformed(self.stats, exc))]
        return [*actions, Hangup(peer)]

    def receive(self, peer: Peer, frame: Frame, now: float, size: int = 0) -> list[Action]:
        """One decoded frame from ``peer`` (``size``: the datagram's, for UDP)."""
        self.stats.requests += 1
        if frame.type not in REQUEST_TYPES:
            error = FrameError(f"{frame.type.name} is not a request")
            return small_reply(peer, error_frame(self.stats, frame, error), size)
        if frame.type is MessageType.HELLO:
            return self.gate.hello(peer, frame, now, size, self._controller)
        if frame.type is MessageType.AUTH:
            actions, new = self.gate.auth(peer, frame, now, self._controller, size)
            if new is not None and self.control.take(new.id, now):
                self._controller = new
            return actions
        return self._request(peer, frame, now, size)

    def completed(
        self, session: int, seq: int, result: bytes | Exception, now: float
    ) -> list[Action]:
        """A Run finished with ``result`` (its reply payload, or the error it raised)."""
        owner = self._controller
        if owner is None or not self.control.completed(session, now):
            return []  # the session ended meanwhile: nobody to answer
        if isinstance(result, Exception):
            reply_type, payload = MessageType.ERROR, error_payload(self.stats, result)
        elif len(result) > MAX_PAYLOAD:
            too_big = RemoteError(
                f"reply of {len(result)} bytes exceeds the {MAX_PAYLOAD}-byte frame limit"
            )
            reply_type, payload = MessageType.ERROR, error_payload(self.stats, too_big)
        else:
            reply_type, payload = MessageType.OK, result
        return [answer(owner, seq, reply_type, payload)]

    def peer_lost(self, peer: Peer) -> list[Action]:
        """A TCP connection closed: a controller that did not say goodbye is stopped."""
        self.gate.forget(peer.key)
        return self._end("disconnected") if self.controls(peer) else []

    def tick(self, now: float) -> list[Action]:
        """Time passed: the deadman, and handshakes that took too long."""
        self.gate.expire(now)
        lapsed = self.control.tick(now)
        if lapsed is None:
            return []
        self.stats.deadman_stops += 1
        self.stats.deadman_silences.append(lapsed.silent_s)
        told = (
            "session ended: the server's deadman stopped the robot: "
            f"its controller was {lapsed.why}"
        )
        return self._end(lapsed.why, notify=True, told=told)

    def next_deadline(self) -> float | None:
        """When :meth:`tick` next has something to do (the deadman, a handshake that
        takes too long), on the clock the events carry; None: not until another event."""
        due = [t for t in (self.control.due_at(), self.gate.next_expiry()) if t is not None]
        return min(due, default=None)

    def shutdown(self) -> list[Action]:
        return self._end("the server is shutting down", notify=True)

    # -- requests of the controller ----------------------------------------------------------

    def _request(self, peer: Peer, frame: Frame, now: float, size: int) -> list[Action]:
        owner = self._controller
        if owner is None or owner.peer.key != peer.key or owner.id != frame.session:
            return self.ended.answer(peer, frame, size)
        verdict = owner.guard.check(frame.seq)
        if verdict is Verdict.REPEAT:
            self.stats.repeats += 1
            return [Send(peer, owner.guard.cached)]
        if verdict is Verdict.WORKING:
            return [Send(peer, reply_frame(owner, frame.seq, MessageType.WORKING, b""))]
        if verdict is Verdict.STALE:
            self.stats.stale += 1
            return []
        if self.control.in_flight and frame.type not in _WHILE_BUSY:
            return [self._pipelined(owner, frame.seq)]
        self.control.heard(owner.id, now)  # only something new keeps the robot going
        try:
            call = parse_request(frame)
        except FrameError as exc:
            return [answer(owner, frame.seq, MessageType.ERROR, error_payload(self.stats, exc))]
        if isinstance(call, Fetch):
            return [fetch(self.stats, owner, frame.seq, call, self.chunk_size)]
        if isinstance(call, Bye):
            # Stopped before the reply goes: when close() returns, the robot stands still.
            data = reply_frame(owner, frame.seq, MessageType.OK, b"")
            return [*self._end("said goodbye", level=logging.INFO), Send(peer, data)]
        if self.control.dispatch(owner.id, now) is not None:  # checked above: never
            return [self._pipelined(owner, frame.seq)]
        owner.guard.begin(frame.seq)
        if frame.type is MessageType.STEP:
            self.stats.steps += 1
        elif frame.type is MessageType.CAMERA_OPEN:
            owner.camera_open = True
        return [Run(peer, owner.id, frame.seq, call)]

    def _pipelined(self, owner: ControllerState, seq: int) -> Send:
        """A request sent while another of the session runs: refused, not queued, so that
        a controller cannot stack up work that would drive the robot after it is gone."""
        self.stats.pipelined += 1
        owner.pipelined += 1
        running = owner.guard.running
        if owner.pipelined == 1:
            log.warning(
                "%s sends requests without waiting for replies: refused, one at a time",
                owner.peer.label,
            )
        error = FrameError(
            f"request {seq} came while request {running} was still running: "
            "one request at a time, wait for each reply"
        )
        payload = error_payload(self.stats, error)
        return Send(owner.peer, reply_frame(owner, seq, MessageType.ERROR, payload))

    def _end(
        self,
        reason: str,
        *,
        notify: bool = False,
        level: int = logging.WARNING,
        told: str | None = None,
    ) -> list[Action]:
        """The controller is gone: stop the robot, remember why its session ended (what
        its client is ``told``: by default that the session ended for ``reason``)."""
        owner, self._controller = self._controller, None
        if owner is None:
            return []
        self.control.release(owner.id)  # already free if the deadman lapsed it
        message = told or f"session ended: {reason}; the robot was stopped"
        self.ended.remember(owner.id, message, owner.peer)
        actions: list[Action] = [
            StopRobot(f"{owner.peer.label} {reason}", owner.camera_open, level)
        ]
        if notify:
            data = encode_frame(MessageType.ERROR, 0, ended_payload(message), owner.id, owner.key)
            actions += [Send(owner.peer, data), Hangup(owner.peer)]
        return actions

    def _taken(self, session: int) -> bool:
        owner = self._controller
        return session in self.ended or (owner is not None and owner.id == session)
