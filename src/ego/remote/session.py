"""``ego serve``'s conversation with its clients as a state machine, without I/O (as h11).

:class:`Session` is fed what arrives (a frame from a peer, a datagram, a finished robot
call, a lost connection, the passing of time) and returns what to do as
:data:`Action` values: send these bytes to that peer, run this call on the robot, stop
the robot, hang up. A thin asyncio adapter (:mod:`ego.remote.server`) performs them over
TCP and UDP; the tests drive the session directly, with a fake clock.

Its parts:

* the handshake (:mod:`ego.remote.handshake`): stateless UDP cookies, the server's proof,
  the client's proof checked in constant time, failures answered one at a time and
  later for a guessing host (:class:`~ego.remote.auth.FailureThrottle`), the session
  key that seals every later frame;
* dedup (:class:`~ego.remote.wire.SequenceGuard`): a repeated request is answered from
  the cache and never runs twice; an older one is ignored;
* the deadman: once the controller has been silent for ``deadline_s`` (nothing new, not
  even a heartbeat; repeats and stale frames do not count) the robot is stopped;
* the dispatch: a request is parsed once into a typed call (:mod:`ego.remote.messages`)
  and handed to the adapter to run, or answered here (FETCH of a big reply's slices).
"""

from __future__ import annotations

import collections
import logging
from collections.abc import Callable

from ego.errors import EgoError, FrameError, LinkLostError, RemoteError, VersionMismatchError
from ego.remote.actions import (
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
from ego.remote.auth import FailureThrottle
from ego.remote.gate import Gate
from ego.remote.messages import Bye, Fetch, parse_request
from ego.remote.wire import (
    MAX_PAYLOAD,
    PROTOCOL_VERSION,
    REQUEST_TYPES,
    SEALED_OVERHEAD,
    Frame,
    FrameKey,
    MessageType,
    Verdict,
    decode_frame,
    encode_frame,
    error_fields,
    pack_error,
    peek_session,
    split_reply,
)

__all__ = ["MAX_EXPIRED", "Session"]

log = logging.getLogger(__name__)

#: Ended sessions remembered, so that their late requests get a clear "expired".
MAX_EXPIRED = 64


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
        self.deadline_s = deadline_s
        self.chunk_size = chunk_size
        self.stats = ServerStats()
        self._controller: ControllerState | None = None
        self._expired: collections.OrderedDict[int, str] = collections.OrderedDict()
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
    def controller(self) -> Peer | None:
        return self._controller.peer if self._controller else None

    def controls(self, peer: Peer) -> bool:
        return self._controller is not None and self._controller.peer.key == peer.key

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
            return small_reply(peer, self._malformed(exc), len(data))
        except FrameError as exc:
            # Garbage gets no answer over UDP: a corrupted datagram is sent again by its
            # sender, and answering forged ones would make the server an amplifier.
            self._count_bad(peer, exc, sealed=key is not None)
            return []
        return self.receive(peer, frame, now, len(data))

    def stream_error(self, peer: Peer, exc: FrameError) -> list[Action]:
        """A TCP stream that cannot be read on: say why (unless forged), hang up."""
        owner = self._controller
        forged = owner is not None and owner.peer.key == peer.key and owner.key is not None
        self._count_bad(peer, exc, sealed=forged)
        actions: list[Action] = [] if forged else [Send(peer, self._malformed(exc))]
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
            actions, new = self.gate.auth(peer, frame, now, self._controller)
            if new is not None:
                self._controller = new
            return actions
        return self._request(peer, frame, now)

    def completed(
        self, session: int, seq: int, result: bytes | Exception, now: float
    ) -> list[Action]:
        """A Run finished with ``result`` (its reply payload, or the error it raised)."""
        owner = self._controller
        if owner is None or owner.id != session:
            return []  # the session ended meanwhile: nobody to answer
        owner.busy -= 1
        owner.last_heard = now
        if isinstance(result, Exception):
            reply_type, payload = MessageType.ERROR, self._error_payload(result)
        elif len(result) > MAX_PAYLOAD:
            too_big = RemoteError(
                f"reply of {len(result)} bytes exceeds the {MAX_PAYLOAD}-byte frame limit"
            )
            reply_type, payload = MessageType.ERROR, self._error_payload(too_big)
        else:
            reply_type, payload = MessageType.OK, result
        data = self._reply(owner, seq, reply_type, payload)
        owner.guard.done(seq, data)
        return [Send(owner.peer, data)]

    def peer_lost(self, peer: Peer) -> list[Action]:
        """A TCP connection closed: a controller that did not say goodbye is stopped."""
        self.gate.forget(peer.key)
        return self._end("disconnected") if self.controls(peer) else []

    def tick(self, now: float) -> list[Action]:
        """Time passed: the deadman, and handshakes that took too long."""
        self.gate.expire(now)
        owner = self._controller
        if owner is None or owner.busy:
            return []
        silent_s = now - owner.last_heard
        if silent_s <= self.deadline_s:
            return []
        self.stats.deadman_stops += 1
        why = f"silent for {silent_s * 1e3:.0f} ms (deadline {self.deadline_s * 1e3:.0f} ms)"
        return self._end(why, notify=True)

    def shutdown(self) -> list[Action]:
        return self._end("the server is shutting down", notify=True)

    # -- requests of the controller ----------------------------------------------------------

    def _request(self, peer: Peer, frame: Frame, now: float) -> list[Action]:
        owner = self._controller
        if owner is None or owner.peer.key != peer.key or owner.id != frame.session:
            return self._not_in_control(peer, frame)
        verdict = owner.guard.check(frame.seq)
        if verdict is Verdict.REPEAT:
            self.stats.repeats += 1
            return [Send(peer, owner.guard.cached)]
        if verdict is Verdict.WORKING:
            return [Send(peer, self._reply(owner, frame.seq, MessageType.WORKING, b""))]
        if verdict is Verdict.STALE:
            self.stats.stale += 1
            return []
        owner.last_heard = now  # only something new keeps the robot going
        try:
            call = parse_request(frame)
        except FrameError as exc:
            return [self._answer(owner, frame.seq, MessageType.ERROR, self._error_payload(exc))]
        if isinstance(call, Fetch):
            return [self._fetch(owner, frame.seq, call)]
        if isinstance(call, Bye):
            # Stopped before the reply goes: when close() returns, the robot stands still.
            data = self._reply(owner, frame.seq, MessageType.OK, b"")
            return [*self._end("said goodbye", level=logging.INFO), Send(peer, data)]
        owner.guard.begin(frame.seq)
        owner.busy += 1
        if frame.type is MessageType.STEP:
            self.stats.steps += 1
        elif frame.type is MessageType.CAMERA_OPEN:
            owner.camera_open = True
        return [Run(peer, owner.id, frame.seq, call)]

    def _not_in_control(self, peer: Peer, frame: Frame) -> list[Action]:
        if frame.type is MessageType.BYE:  # saying goodbye twice is fine
            return [Send(peer, encode_frame(MessageType.OK, frame.seq, b"", frame.session))]
        why = self._expired.get(frame.session)
        message = (
            f"session ended: {why}; the robot was stopped"
            if why
            else "no such session on this server: connect first"
        )
        return [Send(peer, error_frame(self.stats, frame, LinkLostError(message)))]

    def _fetch(self, owner: ControllerState, seq: int, fetch: Fetch) -> Send:
        big = owner.big
        try:
            if big is None or big[0] != fetch.seq:
                raise FrameError(f"no big reply to request {fetch.seq} to fetch from")
            limit = owner.peer.datagram or self.chunk_size
            part = split_reply(big[1], big[2], fetch.offset, limit)
        except FrameError as exc:
            return self._answer(owner, seq, MessageType.ERROR, self._error_payload(exc))
        return self._answer(owner, seq, MessageType.PART, part)

    def _answer(
        self, owner: ControllerState, seq: int, reply_type: MessageType, payload: bytes
    ) -> Send:
        data = self._reply(owner, seq, reply_type, payload)
        owner.guard.done(seq, data)
        return Send(owner.peer, data)

    def _reply(
        self, owner: ControllerState, seq: int, reply_type: MessageType, payload: bytes
    ) -> bytes:
        limit = owner.peer.datagram
        if limit is not None and SEALED_OVERHEAD + len(payload) > limit:
            owner.big = (seq, reply_type, payload)
            payload, reply_type = split_reply(reply_type, payload, 0, limit), MessageType.PART
        return encode_frame(reply_type, seq, payload, owner.id, owner.key)

    def _end(
        self, reason: str, *, notify: bool = False, level: int = logging.WARNING
    ) -> list[Action]:
        """The controller is gone: stop the robot, remember why its session ended."""
        owner, self._controller = self._controller, None
        if owner is None:
            return []
        self._expired[owner.id] = reason
        while len(self._expired) > MAX_EXPIRED:
            self._expired.popitem(last=False)
        actions: list[Action] = [
            StopRobot(f"{owner.peer.label} {reason}", owner.camera_open, level)
        ]
        if notify:
            message = f"session ended: {reason}; the robot was stopped"
            payload = pack_error("LinkLostError", message)
            data = encode_frame(MessageType.ERROR, 0, payload, owner.id, owner.key)
            actions += [Send(owner.peer, data), Hangup(owner.peer)]
        return actions

    def _taken(self, session: int) -> bool:
        owner = self._controller
        return session in self._expired or (owner is not None and owner.id == session)

    # -- errors ------------------------------------------------------------------------------

    def _error_payload(self, exc: Exception) -> bytes:
        if isinstance(exc, EgoError):
            self.stats.errors[type(exc).__name__] += 1
            return pack_error(type(exc).__name__, str(exc), error_fields(exc))
        self.stats.errors["internal"] += 1
        return pack_error("RemoteError", f"internal server error: {exc!r}")

    def _malformed(self, exc: FrameError) -> bytes:
        self.stats.malformed += 1
        if isinstance(exc, VersionMismatchError):
            message = (
                f"ego remote protocol {PROTOCOL_VERSION} here, {exc.peer_version} there: "
                "install the same ego version on both ends"
            )
            payload = pack_error("RemoteError", message)
            return encode_frame(MessageType.ERROR, exc.seq, payload, exc.session)
        return encode_frame(MessageType.ERROR, 0, pack_error("FrameError", str(exc)))

    def _count_bad(self, peer: Peer, exc: FrameError, *, sealed: bool) -> None:
        if sealed:
            self.stats.forged += 1
            log.info("%s: dropped a forged or altered frame: %s", peer.label, exc)
        else:
            self.stats.malformed += 1
            log.debug("%s: dropped a malformed frame: %s", peer.label, exc)
