"""An attacker on the same network, on loopback: nothing can be injected into a session,
altered or replayed, and floods leave the legitimate client in control.

The attacks are the ones a security review of ``ego serve`` ran (issue 17): spoofed and
replayed UDP datagrams from the client's own address, a relay that rewrites TCP frames,
sockets and handshakes by the hundred. The server always has a shared secret here: that
is what a robot reachable from other machines must have (``check_listen``).
"""

from __future__ import annotations

import subprocess
import time
from collections.abc import Iterator

import pytest
from helpers import wait_until
from remote_helpers import (
    DatagramProxy,
    RawClient,
    ServeFactory,
    StreamRelay,
    assert_deadman_fired,
)

from benchmarks.floods import start_flood
from ego.backends.remote.channel import RemoteChannel
from ego.errors import LinkLostError, RobotResetError
from ego.net.frames import HEADER, MAGIC, PROTOCOL_VERSION, MessageType, encode_frame
from ego.net.messages import pack_step
from ego.net.payloads import pack_json
from ego.seam.batch import Request
from ego.seam.profile import Command
from ego.serial.link import LinkSettings
from ego.serial.protocol import encode_batch

SECRET = "s3cret-s3cret-s3cret"
ONE_TRY = LinkSettings(retries=0, reconnect_timeout_s=0.0)
HIJACK = pack_step((Request(Command.SET_SPEED, (-900, 900)),))


def _speeds(channel: RemoteChannel, left: int, right: int) -> tuple[float, ...]:
    batch = encode_batch(
        [Request(Command.SET_SPEED, (left, right)), Request(Command.GET_SPEED)], channel.profile
    )
    return batch.decode(channel.exchange(batch))[1]


def _speeds_applied(channel: RemoteChannel, left: int, right: int, tries: int = 5) -> int:
    """Set the speeds until the robot confirms them, re-applying them after each
    RobotResetError (a session the server ended); how many resets that took."""
    for resets in range(tries):
        try:
            assert _speeds(channel, left, right) == (left, right)
        except RobotResetError:
            continue
        return resets
    raise AssertionError(f"{tries} sessions in a row ended before one step got through")


def _session_of(datagram: bytes) -> int:
    return int(HEADER.unpack_from(datagram)[3])


@pytest.fixture
def udp_session(serve: ServeFactory) -> Iterator[tuple[object, DatagramProxy, RemoteChannel]]:
    served = serve(kinds=("udp",), secret=SECRET, require_secret=True)
    with DatagramProxy(served.url) as proxy:
        channel = RemoteChannel.from_url(proxy.url, SECRET, settings=ONE_TRY)
        try:
            yield served, proxy, channel
        finally:
            channel.close()


def test_a_spoofed_udp_step_from_the_clients_address_is_dropped(
    udp_session: tuple[object, DatagramProxy, RemoteChannel],
) -> None:
    served, proxy, channel = udp_session
    assert _speeds(channel, 200, 200) == (200, 200)
    session = _session_of(proxy.up[-1])  # the session id travels in clear
    seq = int(HEADER.unpack_from(proxy.up[-1])[4])
    for forged in (
        encode_frame(MessageType.STEP, seq + 1, HIJACK, session),  # CRC, no MAC
        encode_frame(MessageType.STEP, seq + 10**6, HIJACK, session),  # far ahead
        proxy.up[-1][:-16] + bytes(16),  # a real frame with a made-up MAC
    ):
        proxy.inject(forged)
    # One source, one socket: the server takes them in order; once the third is counted,
    # all three have had whatever effect they would have.
    assert wait_until(lambda: served.server.stats.forged == 3)  # type: ignore[attr-defined]
    assert served.emu.world.speeds == (200, 200)  # type: ignore[attr-defined]
    for _ in range(5):  # the client's own sequence numbers still count
        assert _speeds(channel, 100, 100) == (100, 100)


@pytest.mark.usefixtures("settled_heap")
def test_a_replayed_udp_session_neither_runs_again_nor_keeps_the_robot_going(
    udp_session: tuple[object, DatagramProxy, RemoteChannel],
) -> None:
    served, proxy, channel = udp_session
    channel.heartbeat = False
    for speed in (100, 200, 300):
        _speeds(channel, speed, speed)
    recorded = list(proxy.up)
    history = len(served.emu.history)  # type: ignore[attr-defined]
    channel.stop_heartbeat()  # the controller dies, its heartbeat with it
    stats = served.server.stats  # type: ignore[attr-defined]
    started = time.monotonic()
    while not stats.deadman_stops and time.monotonic() - started < 10:
        for datagram in recorded:  # the attacker replays all it recorded, on and on
            proxy.inject(datagram)
        time.sleep(0.02)  # the attacker's pace, not a wait for anything
    # The replays kept nothing alive: the deadman counted from the last genuine request.
    assert_deadman_fired(served.server, served.server.deadline_s)  # type: ignore[attr-defined]
    assert wait_until(lambda: served.emu.world.speeds == (0, 0))  # type: ignore[attr-defined]
    # Nothing replayed reached the robot: only the deadman's stop batch came after.
    assert len(served.emu.history) - history == 1  # type: ignore[attr-defined]


@pytest.mark.parametrize("direction", ["up", "down"])
def test_a_relay_that_rewrites_a_frame_is_caught_and_never_yields_a_wrong_value(
    serve: ServeFactory, direction: str
) -> None:
    """After a valid handshake, a relay changes a STEP's speeds (up) or a reply's (down)."""
    served = serve(kinds=("tcp",), secret=SECRET, require_secret=True)

    def rewrite(way: str, index: int, frame: bytes) -> bytes:
        if way != direction or index != 4:  # HELLO, AUTH, then two steps pass untouched
            return frame
        forged = bytearray(frame)
        forged[HEADER.size + 2] ^= 0x40  # a bit of the first argument or reply value
        return bytes(forged)

    with StreamRelay(served.url, rewrite) as relay:
        channel = RemoteChannel.from_url(relay.url, SECRET, settings=ONE_TRY, heartbeat=False)
        try:
            seen = [_speeds(channel, 200, 200), _speeds(channel, 200, 200)]
            with pytest.raises((LinkLostError, RobotResetError)):
                seen.append(_speeds(channel, 200, 200))
        finally:
            channel.close()
        assert relay.counts[f"rewritten {direction}"] == 1
    assert seen == [(200, 200), (200, 200)]  # never a rewritten value
    assert wait_until(lambda: served.emu.world.speeds == (0, 0))  # and the robot stopped
    assert served.server.stats.forged == (1 if direction == "up" else 0)


# -- floods -------------------------------------------------------------------------------


def _flood(
    kind: str, url: str, count: int, seconds: float, extra: bytes = b""
) -> subprocess.Popen[bytes]:
    return start_flood(kind, url, count, seconds, extra)


def _steps_during(channel: RemoteChannel, seconds: float) -> list[float]:
    """Step the robot for ``seconds``; each step's round trip."""
    times = []
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        start = time.monotonic()
        assert _speeds(channel, 150, 150) == (150, 150)
        times.append(time.monotonic() - start)
        time.sleep(0.01)
    return times


@pytest.mark.parametrize("kind", ["idle", "partial"])
def test_the_client_keeps_stepping_through_a_tcp_flood(
    serve: ServeFactory, kind: str, settled_heap: None
) -> None:
    served = serve(kinds=("tcp",), secret=SECRET, require_secret=True, handshake_timeout_s=0.5)
    channel = RemoteChannel.from_url(served.url, SECRET)
    try:
        # Partial frames announce 1 MiB each: refused at the header, before authenticating.
        header = HEADER.pack(MAGIC, PROTOCOL_VERSION, MessageType.HELLO, 0, 1, 1 << 20)
        flood = _flood(kind, served.url, 200, 2.0, header if kind == "partial" else b"")
        try:
            times = _steps_during(channel, 1.5)
        finally:
            flood.wait(timeout=10)
        assert served.server.stats.deadman_stops == 0
        print(
            f"{kind} flood: {len(times)} steps, worst {max(times) * 1e3:.1f} ms",
            served.server.stats,
        )
        # The client kept control: every step was answered, and right (_steps_during), and
        # the deadman never fired. How fast is the security benchmark's to measure, beside
        # the idle case in one run: two busy processes beside this test once made a step
        # take 0.9 s, which says nothing about the flood.
        assert times
        assert served.server.stats.dropped + served.server.stats.malformed > 50
    finally:
        channel.close()


def test_a_udp_hello_flood_from_many_ports_keeps_no_state_and_every_client_gets_in(
    serve: ServeFactory,
) -> None:
    served = serve(kinds=("udp",), secret=SECRET, require_secret=True)
    hello = encode_frame(
        MessageType.HELLO, 1, pack_json({"nonce": bytes(32).hex(), "pad": "-" * 400})
    )
    flood = _flood("hello", served.url, 32, 2.0, hello)
    try:
        assert wait_until(lambda: served.server.stats.cookies > 0)  # the flood has begun
        for _ in range(20):  # twenty handshakes in a row, all through
            # However long a loaded machine takes to reach the HELLO in the flood: the
            # promise is that it gets in, not how fast (the security benchmark's). The
            # client retransmits its handshake until its connect timeout.
            channel = RemoteChannel.from_url(served.url, SECRET, heartbeat=False,
                                             connect_timeout_s=20.0)  # fmt: skip
            assert _speeds(channel, 0, 0) == (0, 0)
            channel.close()
            # One client at a time: the next gets in once the server has let this one go
            # (by its goodbye, or by the deadman if the flood lost the goodbye).
            assert wait_until(lambda: served.server.controller is None)
    finally:
        flood.wait(timeout=10)
    assert not served.server.session.gate._pending  # spoofable HELLOs left no state
    assert served.server.stats.cookies > 100


@pytest.mark.parametrize("kind", ["idle", "hello"])
def test_the_deadman_fires_on_time_under_a_flood(
    serve: ServeFactory, kind: str, settled_heap: None
) -> None:
    deadline_s = 0.5
    kinds = ("tcp",) if kind == "idle" else ("udp",)
    served = serve(kinds=kinds, secret=SECRET, require_secret=True, deadline_s=deadline_s)
    hello = encode_frame(
        MessageType.HELLO, 1, pack_json({"nonce": bytes(32).hex(), "pad": "-" * 400})
    )
    flood = _flood(
        kind, served.url, 100 if kind == "idle" else 32, 3.0, hello if kind == "hello" else b""
    )
    stats = served.server.stats
    try:
        peers = served.server.peers
        assert wait_until(lambda: stats.cookies + stats.dropped + len(peers.half_open))  # begun
        channel = RemoteChannel.from_url(served.url, SECRET, heartbeat=False,
                                         connect_timeout_s=20.0)  # fmt: skip
        # The flood may drown the first step's datagrams for longer than the deadline: the
        # server's deadman then ends that session (on time, as below) and the client says
        # so with RobotResetError. The controller re-applies its speeds, as it must.
        resets = _speeds_applied(channel, 300, 300)
        # Then the controller hangs: nothing more is sent.
        assert_deadman_fired(served.server, deadline_s, times=1 + resets)  # server's clock
        assert wait_until(lambda: served.emu.world.speeds == (0, 0))
    finally:
        flood.wait(timeout=10)


def test_a_stranger_gets_at_most_a_small_frame_before_authenticating(
    serve: ServeFactory,
) -> None:
    served = serve(kinds=("tcp",), secret=SECRET, require_secret=True)
    raw = RawClient(served.url)
    raw.send_raw(HEADER.pack(MAGIC, PROTOCOL_VERSION, MessageType.HELLO, 0, 1, 2048))
    reply = raw.receive()
    raw.close()
    assert reply.type is MessageType.ERROR and b"1024-byte limit" in reply.payload
