"""Who may control the robot: ``ego serve``'s handshake as a state machine, without I/O.

It answers HELLO and AUTH (:mod:`ego.net.handshake` says how the exchange goes and
why), keeps the handshakes in progress (at most one per peer, at most MAX_PENDING in
all, the oldest forgotten first), makes UDP clients prove their address with a
stateless cookie before it keeps anything, and holds a wrong proof's answer back
(:class:`~ego.net.auth.FailureThrottle`). A proven client comes out as the new
:class:`~ego.servers.sessions.actions.ControllerState`, with the key its frames are sealed with.
"""

from __future__ import annotations

import collections
import logging
import secrets
from collections.abc import Callable, Hashable

from ego.errors import AuthenticationError, FrameError, RobotBusyError
from ego.net.auth import FailureThrottle, new_nonce
from ego.net.frames import Frame, FrameKey, MessageType, encode_frame
from ego.net.handshake import (
    CookieJar,
    auth_proof,
    challenge,
    client_proved,
    parse_hello,
    session_key,
)
from ego.net.payloads import pack_json
from ego.net.sequence import Verdict
from ego.servers.sessions.actions import (
    Action,
    Authenticated,
    ControllerState,
    Hangup,
    Peer,
    PendingHandshake,
    Send,
    ServerStats,
    error_frame,
    small_reply,
)

__all__ = ["MAX_PENDING", "Gate"]

log = logging.getLogger(__name__)

#: Handshakes started but not finished that are remembered (one per peer).
MAX_PENDING = 64


class Gate:
    """The handshakes in progress, and the checks a client passes to take control."""

    def __init__(
        self,
        stats: ServerStats,
        *,
        secret: bytes | None,
        welcome: Callable[[], dict[str, object]],
        handshake_timeout_s: float,
        throttle: FailureThrottle,
        udp_cookies: bool,
        taken: Callable[[int], bool],
    ) -> None:
        self.stats = stats
        self.secret = secret
        self.handshake_timeout_s = handshake_timeout_s
        self._welcome = welcome
        self._throttle = throttle
        self._cookies = CookieJar() if udp_cookies else None
        #: Whether a session id is in use or remembered (ids are never reused soon).
        self._taken = taken
        self._pending: collections.OrderedDict[Hashable, PendingHandshake] = (
            collections.OrderedDict()
        )

    def forget(self, peer_key: Hashable) -> None:
        self._pending.pop(peer_key, None)

    def next_expiry(self) -> float | None:
        """When the oldest pending handshake expires, or None."""
        if not self._pending:
            return None
        return min(p.created for p in self._pending.values()) + self.handshake_timeout_s

    def expire(self, now: float) -> None:
        for key, pending in list(self._pending.items()):
            if now - pending.created > self.handshake_timeout_s:
                del self._pending[key]

    def hello(
        self, peer: Peer, frame: Frame, now: float, size: int, owner: ControllerState | None
    ) -> list[Action]:
        pending = self._pending.get(peer.key)
        if pending is not None and pending.hello_payload == frame.payload:
            return [Send(peer, pending.guard.cached)]  # retransmitted: the same challenge
        if (
            owner is not None
            and owner.peer.key == peer.key
            and owner.hello_payload == frame.payload
        ):
            return []  # a late duplicate of the controller's own HELLO
        try:
            hello = parse_hello(frame.payload)
        except FrameError as exc:
            bad = FrameError(f"malformed HELLO: {exc}")
            return small_reply(peer, error_frame(self.stats, frame, bad), size)
        cookies = self._cookies
        if (
            peer.datagram is not None
            and cookies is not None
            and not cookies.check(hello.cookie, peer.label, hello.nonce, now)
        ):
            self.stats.cookies += 1
            cookie = cookies.make(peer.label, hello.nonce, now)
            reply = pack_json({"cookie": cookie.hex()})
            return small_reply(peer, encode_frame(MessageType.COOKIE, frame.seq, reply), size)
        if owner is not None:
            self.stats.refused += 1
            log.info("%s: refused, the robot is controlled by %s", peer.label, owner.peer.label)
            busy = RobotBusyError(
                f"the robot is already controlled by {self.who(owner)} (one client at a time)"
            )
            return small_reply(peer, error_frame(self.stats, frame, busy), size)
        pending = PendingHandshake(peer, self._new_id(), hello, frame.payload, new_nonce(), now)
        payload = challenge(self.secret, hello, pending.server_nonce, pending.id)
        data = encode_frame(MessageType.OK, frame.seq, payload, pending.id)
        pending.guard.done(frame.seq, data)
        self._pending[peer.key] = pending
        while len(self._pending) > MAX_PENDING:
            self._pending.popitem(last=False)
        return small_reply(peer, data, size)

    def auth(
        self, peer: Peer, frame: Frame, now: float, owner: ControllerState | None, size: int = 0
    ) -> tuple[list[Action], ControllerState | None]:
        """The actions answering an AUTH (``size``: the datagram's, for UDP), and the new
        controller if the client proved itself."""
        if owner is not None and owner.peer.key == peer.key and owner.id == frame.session:
            if owner.guard.check(frame.seq) is Verdict.REPEAT:
                return [Send(peer, owner.guard.cached)], None  # the welcome was lost: again
            return [], None
        pending = self._pending.get(peer.key)
        if pending is None or pending.id != frame.session:
            # Nothing proves this peer's address: no answer bigger than what it sent.
            error = AuthenticationError("no handshake in progress for this session: connect again")
            return small_reply(peer, error_frame(self.stats, frame, error), size), None
        verdict = pending.guard.check(frame.seq)
        if verdict is Verdict.REPEAT:
            return [Send(peer, pending.guard.cached)], None
        if verdict is Verdict.WORKING:  # retransmitted while a wrong proof is held back
            return [Send(peer, encode_frame(MessageType.WORKING, frame.seq, b"", pending.id))], None
        if verdict is Verdict.STALE:
            return [], None
        pending.guard.begin(frame.seq)
        try:
            proof = auth_proof(frame.payload)
        except FrameError as exc:
            del self._pending[peer.key]
            bad = FrameError(f"malformed AUTH: {exc}")
            return [Send(peer, error_frame(self.stats, frame, bad))], None
        if self.secret is not None and not client_proved(
            self.secret, pending.hello, pending.server_nonce, pending.id, proof
        ):
            self.stats.refused += 1
            log.warning("%s: refused, wrong shared secret", peer.label)
            # Kept until it expires: a retransmission meanwhile is told WORKING.
            delay = self._throttle.failed(peer.host, now)
            why = "wrong shared secret" if proof else "this server requires a shared secret"
            data = error_frame(self.stats, frame, AuthenticationError(why))
            return [Send(peer, data, delay), Hangup(peer, delay)], None
        del self._pending[peer.key]
        if owner is not None:
            self.stats.refused += 1
            busy = RobotBusyError(f"the robot is already controlled by {self.who(owner)}")
            return [Send(peer, error_frame(self.stats, frame, busy))], None
        key = None
        if self.secret is not None:
            raw = session_key(self.secret, pending.hello.nonce, pending.server_nonce, pending.id)
            key = FrameKey(raw, server=True)
        new = ControllerState(peer, pending.id, key, pending.hello_payload)
        data = encode_frame(MessageType.OK, frame.seq, pack_json(self._welcome()), new.id, key)
        new.guard.done(frame.seq, data)
        self.stats.sessions += 1
        log.info("%s controls the robot (session %08x)", peer.label, new.id)
        return [Authenticated(peer, key), Send(peer, data)], new

    def who(self, owner: ControllerState) -> str:
        """The controller, as told to a refused client: its address only where anyone may
        connect anyway (with a secret, a stranger learns nothing)."""
        return "another client" if self.secret is not None else owner.peer.label

    def _new_id(self) -> int:
        while True:
            sid = secrets.randbits(32)
            if sid and not self._taken(sid):
                return sid
