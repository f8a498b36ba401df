"""UDP reflection: ``ego serve`` never answers a peer that has not proven its address with
more bytes than it was sent, whatever the datagram.

Otherwise an attacker who forges a victim's source address makes the server send the
victim more than the attacker spent (issue 22 measured 7.15x: 20 bytes in, 143 out).
Every kind of datagram is sent from a socket that never completed a handshake: each
message type, in and out of a session, malformed, truncated, of another version; with
another client in control, with its session id too. After each, a padded HELLO serves as
a marker: the server answers datagrams in order, so every reply before the marker's is
the reply to the datagram under test.
"""

from __future__ import annotations

import pytest
from abuse import reflect_all
from helpers import wait_until
from remote_helpers import ConnectFactory, ServeFactory

SECRET = "s3cret-s3cret-s3cret"


@pytest.mark.parametrize("secret", [None, SECRET], ids=["no secret", "secret"])
def test_no_datagram_from_an_unproven_peer_is_answered_with_more_than_it_sent(
    serve: ServeFactory, connect: ConnectFactory, secret: str | None
) -> None:
    served = serve(kinds=("udp",), secret=secret, deadline_s=0.2)
    gone = connect(served.url, secret=secret, heartbeat=False)
    ended = gone._conn.session  # type: ignore[attr-defined]
    assert wait_until(lambda: served.server.controller is None)  # the deadman ended it
    controller = connect(served.url, secret=secret)  # another client holds the robot
    probes = reflect_all(served.url, controller._conn.session, ended)  # type: ignore[attr-defined]
    assert len(probes) > 80
    amplified = [p for p in probes if p.answered > p.sent]
    assert not amplified, [(p.name, p.sent, p.answered) for p in amplified]
    assert any(p.answered for p in probes)  # what fits is still answered
    assert served.server.controller is not None  # the controller kept its robot
