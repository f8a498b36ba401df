"""The sessions ``ego serve`` ended, and what their late requests are told (no I/O).

A request of an ended session is answered with why it ended (the deadman stopped the
robot, the client said goodbye...), marked ``session_ended`` so that the client knows
its session is over rather than a frame lost. Over UDP that answer may go to a forged
source address: it is never bigger than the request (no amplification), except to the
address that controlled the session, which its handshake proved.
"""

from __future__ import annotations

import collections
from collections.abc import Hashable

from ego.errors import LinkLostError
from ego.net.frames import Frame, MessageType, encode_frame
from ego.net.payloads import pack_error
from ego.servers.sessions.actions import Action, Peer, Send, ServerStats, error_frame, small_reply

__all__ = ["MAX_EXPIRED", "EndedSessions", "ended_payload"]

#: Ended sessions remembered, so that their late requests get a clear "expired".
MAX_EXPIRED = 64


def ended_payload(message: str) -> bytes:
    """The ERROR payload telling a client that its session is over, and why."""
    return pack_error("LinkLostError", message, {"session_ended": True})


class EndedSessions:
    """The last MAX_EXPIRED sessions that ended: why, and which peer controlled each."""

    def __init__(self, stats: ServerStats) -> None:
        self.stats = stats
        self._ended: collections.OrderedDict[int, tuple[str, Hashable]] = collections.OrderedDict()

    def __contains__(self, session: int) -> bool:
        return session in self._ended

    def remember(self, session: int, message: str, peer: Peer) -> None:
        self._ended[session] = (message, peer.key)
        while len(self._ended) > MAX_EXPIRED:
            self._ended.popitem(last=False)

    def answer(self, peer: Peer, frame: Frame, size: int) -> list[Action]:
        """The answer to a request outside the session in control (``size``: the
        datagram's, for UDP)."""
        if frame.type is MessageType.BYE:  # saying goodbye twice is fine
            ok = encode_frame(MessageType.OK, frame.seq, b"", frame.session)
            return small_reply(peer, ok, size)
        ended = self._ended.get(frame.session)
        if ended is None:
            error = LinkLostError("no such session on this server: connect first")
            return small_reply(peer, error_frame(self.stats, frame, error), size)
        message, controlled_by = ended
        self.stats.errors["LinkLostError"] += 1
        data = encode_frame(MessageType.ERROR, frame.seq, ended_payload(message), frame.session)
        return [Send(peer, data)] if controlled_by == peer.key else small_reply(peer, data, size)
