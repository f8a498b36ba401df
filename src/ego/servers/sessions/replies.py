"""How ``ego serve``'s socket session words its replies (no I/O): sealed frames for the
controller (split into PARTs where a datagram cannot hold them), ERROR payloads, and
the answers to frames that could not be read."""

from __future__ import annotations

import logging

from ego.errors import EgoError, FrameError, VersionMismatchError
from ego.net.frames import PROTOCOL_VERSION, SEALED_OVERHEAD, MessageType, encode_frame
from ego.net.messages import Fetch
from ego.net.payloads import error_fields, pack_error, split_reply
from ego.servers.sessions.actions import ControllerState, Peer, Send, ServerStats

__all__ = ["answer", "count_bad", "error_payload", "fetch", "malformed", "reply_frame"]

log = logging.getLogger("ego.servers.sessions.session")


def reply_frame(
    owner: ControllerState, seq: int, reply_type: MessageType, payload: bytes
) -> bytes:
    """A reply to the controller, sealed with its key; over UDP, a reply too big for one
    datagram goes as its first PART (the rest is fetched: :func:`fetch`)."""
    limit = owner.peer.datagram
    if limit is not None and SEALED_OVERHEAD + len(payload) > limit:
        owner.big = (seq, reply_type, payload)
        payload, reply_type = split_reply(reply_type, payload, 0, limit), MessageType.PART
    return encode_frame(reply_type, seq, payload, owner.id, owner.key)


def answer(owner: ControllerState, seq: int, reply_type: MessageType, payload: bytes) -> Send:
    """A reply to the controller, remembered for a retransmitted request."""
    data = reply_frame(owner, seq, reply_type, payload)
    owner.guard.done(seq, data)
    return Send(owner.peer, data)


def fetch(stats: ServerStats, owner: ControllerState, seq: int, call: Fetch, chunk: int) -> Send:
    """The slice of the last big reply a FETCH asks for (``chunk``: a stream's size)."""
    big = owner.big
    try:
        if big is None or big[0] != call.seq:
            raise FrameError(f"no big reply to request {call.seq} to fetch from")
        part = split_reply(big[1], big[2], call.offset, owner.peer.datagram or chunk)
    except FrameError as exc:
        return answer(owner, seq, MessageType.ERROR, error_payload(stats, exc))
    return answer(owner, seq, MessageType.PART, part)


def error_payload(stats: ServerStats, exc: Exception) -> bytes:
    """An ERROR payload naming ``exc`` (an ego error), or an internal error."""
    if isinstance(exc, EgoError):
        stats.errors[type(exc).__name__] += 1
        return pack_error(type(exc).__name__, str(exc), error_fields(exc))
    stats.errors["internal"] += 1
    return pack_error("RemoteError", f"internal server error: {exc!r}")


def malformed(stats: ServerStats, exc: FrameError) -> bytes:
    """The unsealed ERROR answering a frame that could not be read."""
    stats.malformed += 1
    if isinstance(exc, VersionMismatchError):
        message = (
            f"ego remote protocol {PROTOCOL_VERSION} here, {exc.peer_version} there: "
            "install the same ego version on both ends"
        )
        payload = pack_error("RemoteError", message)
        return encode_frame(MessageType.ERROR, exc.seq, payload, exc.session)
    return encode_frame(MessageType.ERROR, 0, pack_error("FrameError", str(exc)))


def count_bad(stats: ServerStats, peer: Peer, exc: FrameError, *, sealed: bool) -> None:
    """A frame dropped unanswered: forged (it failed a session's MAC) or malformed."""
    if sealed:
        stats.forged += 1
        log.info("%s: dropped a forged or altered frame: %s", peer.label, exc)
    else:
        stats.malformed += 1
        log.debug("%s: dropped a malformed frame: %s", peer.label, exc)
