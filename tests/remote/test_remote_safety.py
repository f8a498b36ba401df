"""Safety and access: the deadman, one controller at a time, the shared secret, garbage input."""

from __future__ import annotations

import contextlib
import gc
import logging
import random
import socket
import struct
import threading
import time
import zlib

import pytest
from helpers import wait_until
from remote_helpers import (
    ConnectFactory,
    DatagramProxy,
    RawClient,
    ServeFactory,
    assert_deadman_fired,
)

from ego.backends.remote.channel import RemoteChannel
from ego.errors import AuthenticationError, RobotBusyError, RobotResetError
from ego.net.frames import (
    HEADER,
    MAGIC,
    MAX_DATAGRAM,
    MAX_PAYLOAD,
    MessageType,
    decode_frame,
    encode_frame,
)
from ego.net.messages import pack_step
from ego.net.payloads import pack_json, unpack_error, unpack_json
from ego.seam.batch import Request
from ego.seam.profile import Command
from ego.serial.link import Link
from ego.serial.protocol import encode_batch
from ego.servers.socket.server import Server

DEADLINE_S = 0.3


def _drive(link: Link, left: int, right: int, led: int) -> None:
    """Wheels at (left, right), every LED at ``led``, confirmed by an E in the same batch."""
    requests = [Request(Command.SET_SPEED, (left, right))]
    requests += [Request(Command.SET_LED, (k, led)) for k in link.profile.leds]
    requests.append(Request(Command.GET_SPEED))
    batch = encode_batch(requests, link.profile)
    assert batch.decode(link.exchange(batch))[-1] == (left, right)


# -- the deadman -----------------------------------------------------------------------


@pytest.mark.usefixtures("settled_heap")
def test_silent_client_gets_motors_stopped_and_leds_off_after_the_deadline(
    serve: ServeFactory, connect: ConnectFactory, kind: str
) -> None:
    served = serve(kinds=(kind,), deadline_s=DEADLINE_S)
    link = connect(served.url, heartbeat=False)
    _drive(link, 400, -400, 1)
    world = served.emu.world
    assert world.speeds == (400, -400) and all(world.leds)
    assert_deadman_fired(served.server, DEADLINE_S)
    assert wait_until(lambda: world.speeds == (0, 0) and not any(world.leds)), world
    assert served.server.controller is None


def test_heartbeat_keeps_an_idle_controller_in_control(
    serve: ServeFactory, connect: ConnectFactory, kind: str
) -> None:
    served = serve(kinds=(kind,), deadline_s=DEADLINE_S)
    link = connect(served.url)  # heartbeat on: a controller with a 1 s step
    _drive(link, 250, 250, 1)
    # A timeout, so a time: three deadlines on the clock the server's deadman reads
    # (time.monotonic), a deadman that fires within 10 % of one (README) would have by
    # then; and, however slow the machine, three heartbeats sent meanwhile.
    sent, since = link.net.heartbeats, time.monotonic()  # type: ignore[attr-defined]
    assert wait_until(
        lambda: time.monotonic() - since > 3 * DEADLINE_S
        and link.net.heartbeats >= sent + 3,  # type: ignore[attr-defined]
        10,
    )
    assert served.emu.world.speeds == (250, 250)
    assert served.server.stats.deadman_stops == 0
    assert link.net.heartbeats >= 3  # type: ignore[attr-defined]
    _drive(link, 0, 0, 0)


def test_timed_out_client_reconnects_and_is_told_to_reapply_its_state(
    serve: ServeFactory, connect: ConnectFactory, kind: str
) -> None:
    served = serve(kinds=(kind,), deadline_s=0.2)
    link = connect(served.url, heartbeat=False)
    _drive(link, 300, 300, 0)
    assert wait_until(lambda: served.server.stats.deadman_stops == 1)
    batch = encode_batch([Request(Command.GET_SPEED)], link.profile)
    with pytest.raises(RobotResetError):
        link.exchange(batch)  # the robot was stopped behind its back: say so
    assert link.exchange(batch) == bytes(4)  # stopped, and the new session serves
    assert served.server.stats.sessions == 2


@pytest.mark.filterwarnings("ignore::ResourceWarning")
@pytest.mark.usefixtures("settled_heap")
def test_transport_dropped_without_close_lets_the_deadman_stop_the_robot(
    serve: ServeFactory,
) -> None:
    served = serve(kinds=("udp",), deadline_s=DEADLINE_S)
    link = RemoteChannel.from_url(served.url)  # heartbeat on, never closed
    _drive(link, 300, 300, 1)
    del link
    gc.collect()
    assert_deadman_fired(served.server, DEADLINE_S)
    assert wait_until(lambda: served.emu.world.speeds == (0, 0))


def test_disconnect_without_goodbye_stops_the_robot_at_once(serve: ServeFactory) -> None:
    served = serve(kinds=("tcp",), deadline_s=5.0)
    raw = RawClient(served.url)
    assert raw.handshake().type is MessageType.OK
    batch = encode_batch(
        [Request(Command.SET_SPEED, (300, 300)), Request(Command.GET_SPEED)],
        served.link.profile,
    )
    raw.send(MessageType.STEP, pack_step(batch.requests))
    assert raw.receive().type is MessageType.OK
    assert served.emu.world.speeds == (300, 300)
    raw.close()
    assert wait_until(lambda: served.emu.world.speeds == (0, 0))
    assert served.server.stats.deadman_stops == 0  # at once, not by the 5 s deadman
    assert served.server.controller is None


# -- one controller --------------------------------------------------------------------


def test_second_client_is_refused_while_the_first_controls(
    serve: ServeFactory, connect: ConnectFactory
) -> None:
    served = serve(kinds=("tcp", "udp"))
    first = connect(served.url_of("tcp"))
    for url in served.thread.urls:
        with pytest.raises(RobotBusyError, match=r"already controlled by tcp 127\.0\.0\.1"):
            RemoteChannel.from_url(url)
    _drive(first, 100, 100, 0)  # the first client is untouched
    first.close()
    second = connect(served.url_of("udp"))
    _drive(second, 0, 0, 0)
    assert served.server.stats.refused == 2


# -- the shared secret -----------------------------------------------------------------


def test_wrong_secret_is_refused(serve: ServeFactory, connect: ConnectFactory, kind: str) -> None:
    served = serve(
        kinds=(kind,), secret="s3cret-s3cret-s3cret", require_secret=True, auth_failure_delay_s=0.0
    )
    # Our client checks the server's proof first: a wrong secret never sends its own.
    with pytest.raises(AuthenticationError, match="could not prove it knows our shared secret"):
        RemoteChannel.from_url(served.url, secret="a-wrong-guess-of-16+")
    with pytest.raises(AuthenticationError, match="requires a shared secret"):
        RemoteChannel.from_url(served.url, secret="")
    # A client that guesses anyway is told so.
    raw = RawClient(served.url)
    reply = raw.handshake(proof=bytes(32))
    raw.close()
    assert reply.type is MessageType.ERROR
    assert "wrong shared secret" in unpack_error(reply.payload)[1]
    assert served.server.controller is None
    link = connect(served.url, secret="s3cret-s3cret-s3cret")
    _drive(link, 0, 0, 0)
    assert served.server.stats.refused == 1


def test_busy_robot_with_a_secret_does_not_name_its_controller(
    serve: ServeFactory, connect: ConnectFactory
) -> None:
    served = serve(kinds=("tcp",), secret="s3cret-s3cret-s3cret")
    connect(served.url, secret="s3cret-s3cret-s3cret")
    with pytest.raises(RobotBusyError, match="another client") as info:
        RemoteChannel.from_url(served.url, secret="s3cret-s3cret-s3cret")
    assert "127.0.0.1" not in str(info.value).split(": ", 1)[1]


def test_server_off_loopback_without_a_secret_refuses_to_start(link: Link) -> None:
    with pytest.raises(ValueError, match="shared secret"):
        Server(link, listen="tcp://0.0.0.0:0")  # checked before anything binds
    with pytest.raises(ValueError, match="shared secret"):
        Server(link, listen="udp://127.0.0.1:0", require_secret=True)


def test_secret_never_crosses_the_wire(serve: ServeFactory, connect: ConnectFactory) -> None:
    secret = b"correct horse battery staple"
    served = serve(kinds=("udp",), secret=secret, require_secret=True)
    with DatagramProxy(served.url) as proxy:
        link = connect(proxy.url, secret=secret)
        _drive(link, 0, 0, 0)
        link.close()
    wire = b"".join(proxy.seen)
    assert len(proxy.seen) > 4
    assert secret not in wire and secret.hex().encode() not in wire


@pytest.mark.parametrize(
    "claims", [{"auth": True}, {"auth": False}], ids=["false proof", "no auth"]
)
def test_client_refuses_a_server_that_cannot_prove_the_secret(claims: dict[str, bool]) -> None:
    """An impostor, with a made-up proof or saying no secret is needed, is refused before
    the client gives away a proof of its own."""
    sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    sock.bind(("127.0.0.1", 0))
    sock.settimeout(0.5)
    heard: list[MessageType] = []

    def impostor() -> None:
        with contextlib.suppress(OSError):
            while True:
                data, addr = sock.recvfrom(MAX_DATAGRAM)
                frame = decode_frame(data)
                heard.append(frame.type)
                reply = {"nonce": bytes(32).hex(), "proof": bytes(32).hex(), **claims}
                sock.sendto(encode_frame(MessageType.OK, frame.seq, pack_json(reply), 77), addr)

    thread = threading.Thread(target=impostor, name="impostor")
    thread.start()
    try:
        with pytest.raises(AuthenticationError, match="could not prove"):
            RemoteChannel.from_url(
                f"udp://127.0.0.1:{sock.getsockname()[1]}",
                secret="s3cret-s3cret-s3cret",
                heartbeat=False,
            )
    finally:
        with contextlib.suppress(OSError):
            sock.shutdown(socket.SHUT_RDWR)  # wakes its recvfrom, where a close would not
        sock.close()
        thread.join(timeout=5)
    assert not thread.is_alive(), "the impostor's thread did not end"
    assert heard == [MessageType.HELLO]  # never an AUTH: no proof for the impostor


# -- garbage ---------------------------------------------------------------------------


def _garbage(rng: random.Random, session: int) -> bytes:
    """One malformed or unwelcome frame of a random kind."""
    good = encode_frame(
        rng.choice(list(MessageType)),
        rng.randrange(2**32),
        rng.randbytes(rng.randrange(64)),
        rng.choice((0, session, rng.randrange(2**32))),
    )
    choice = rng.randrange(7)
    if choice == 0:
        return rng.randbytes(rng.randrange(200))
    if choice == 1:  # one bit flipped
        flipped = bytearray(good)
        bit = rng.randrange(len(flipped) * 8)
        flipped[bit // 8] ^= 1 << (bit % 8)
        return bytes(flipped)
    if choice == 2:  # cut short
        return good[: rng.randrange(len(good))]
    if choice == 3:  # a length beyond the limit
        head = HEADER.pack(MAGIC, 1, MessageType.STEP, session, 1, MAX_PAYLOAD + rng.randrange(9))
        return head + zlib.crc32(head).to_bytes(4, "little")
    if choice == 4:  # an unknown type or another version, with a valid CRC
        head = HEADER.pack(MAGIC, rng.choice((1, 2, 255)), rng.randrange(256), session, 1, 0)
        return head + zlib.crc32(head).to_bytes(4, "little")
    return good  # intact, but from a stranger: random type, payload, session


def test_a_thousand_malformed_frames_leave_the_server_serving(
    serve: ServeFactory, connect: ConnectFactory
) -> None:
    served = serve(kinds=("tcp", "udp"))
    link = connect(served.url_of("udp"))
    _drive(link, 200, 200, 1)
    session = link._conn.session  # type: ignore[attr-defined]
    executed = len(served.emu.history)
    rng = random.Random(20240521)
    stats = served.server.stats
    fuzz = RawClient(served.url_of("udp"))
    for chunk in range(40):
        # 25 datagrams at a time, then until the server has read some of them: a busy
        # machine's server falls behind, and the kernel drops what overflows its socket.
        before = stats.malformed
        for _ in range(25):
            fuzz.send_raw(_garbage(rng, session))
        assert wait_until(lambda seen=before: stats.malformed > seen), f"chunk {chunk}: none read"
    fuzz.close()
    for _ in range(20):  # a stream breaks at its first bad frame: one connection each
        raw = RawClient(served.url_of("tcp"), timeout_s=0.5)
        raw.send_raw(b"".join(_garbage(rng, session) for _ in range(5)))
        raw.close()
    assert wait_until(lambda: stats.malformed >= 300), stats
    assert len(served.emu.history) == executed  # not one reached the robot
    assert served.server.controller is not None and "udp" in served.server.controller
    assert served.emu.world.speeds == (200, 200)  # the controller was not disturbed
    _drive(link, 0, 0, 0)  # and it still steps


def test_oversized_frame_is_refused_and_the_connection_closed(
    serve: ServeFactory, connect: ConnectFactory
) -> None:
    served = serve(kinds=("tcp",))
    raw = RawClient(served.url)
    raw.send_raw(HEADER.pack(MAGIC, 1, MessageType.STEP, 0, 1, 2 * MAX_PAYLOAD))
    reply = raw.receive()
    assert reply.type is MessageType.ERROR
    assert unpack_error(reply.payload)[0] == "FrameError"
    assert "exceeds" in unpack_error(reply.payload)[1]
    with pytest.raises((ConnectionError, socket.timeout)):
        raw.receive()
    raw.close()
    _drive(connect(served.url), 0, 0, 0)


def test_other_protocol_version_is_told_both_versions(serve: ServeFactory, kind: str) -> None:
    served = serve(kinds=(kind,))
    raw = RawClient(served.url)
    # Padded: over UDP no answer is bigger than what asked for it (no amplification).
    payload = pack_json({"nonce": bytes(32).hex(), "pad": "-" * 200})
    head = HEADER.pack(MAGIC, 9, MessageType.HELLO, 0, 1, len(payload))
    raw.send_raw(head + payload + struct.pack("<I", zlib.crc32(head + payload)))
    reply = raw.receive()
    raw.close()
    assert reply.type is MessageType.ERROR and reply.seq == 1
    message = unpack_error(reply.payload)[1]
    assert "protocol 2 here, 9 there" in message


def test_request_outside_a_session_is_refused(serve: ServeFactory) -> None:
    served = serve(kinds=("udp",))
    raw = RawClient(served.url, timeout_s=0.3)
    raw.session = 1234
    raw.send(MessageType.STEP, b"\xbb\x00")
    with pytest.raises(TimeoutError):  # the answer would be bigger: no amplification
        raw.receive()
    raw.send(MessageType.STEP, b"\xbb\x00" * 100)  # room for the answer
    reply = raw.receive()
    raw.close()
    assert reply.type is MessageType.ERROR
    assert "no such session" in unpack_error(reply.payload)[1]
    assert len(served.emu.history) == 0


def test_welcome_names_the_firmware_and_deadline(serve: ServeFactory) -> None:
    served = serve(kinds=("udp",), deadline_s=0.4)
    raw = RawClient(served.url)
    welcome = unpack_json(raw.handshake().payload)
    raw.send(MessageType.BYE)
    raw.close()
    assert welcome["firmware"] == "webots"
    assert welcome["deadline_s"] == 0.4


@pytest.mark.usefixtures("settled_heap")
def test_a_long_step_keeps_control_but_a_hung_controller_trips_the_deadman(
    serve: ServeFactory, kind: str
) -> None:
    """Heartbeats come from the step loop: during a 1 s step the session lives; a
    controller stuck in its own code (no step) lets the deadman stop the robot."""
    import ego

    served = serve(kinds=(kind,), deadline_s=DEADLINE_S)
    with ego.Robot(served.url, handle_signals=False) as robot:
        robot.motors.set_speed(250, 250)
        assert robot.step(1000) == 0  # three deadlines long, waited out inside step()
        assert served.server.stats.deadman_stops == 0
        assert served.emu.world.speeds == (250, 250)
        assert_deadman_fired(served.server, DEADLINE_S)  # "hung" in its own code
        assert wait_until(lambda: served.emu.world.speeds == (0, 0))


def test_the_throttle_doubles_per_host_caps_and_forgets() -> None:
    from ego.net.auth import FailureThrottle

    throttle = FailureThrottle(base_s=0.2, max_s=1.0, window_s=60.0)
    delays = [throttle.failed("10.0.0.9", t) for t in range(4)]
    assert delays == pytest.approx([0.2, 0.4, 0.8, 1.0])
    assert throttle.failed("10.0.0.7", 4.0) == pytest.approx(0.2)  # another host: afresh
    assert throttle.failed("10.0.0.9", 100.0) == pytest.approx(0.2)  # a quiet minute forgets


def test_parallel_guesses_are_answered_one_at_a_time_and_slower_each_time(
    serve: ServeFactory, connect: ConnectFactory
) -> None:
    """Online guessing: wrong proofs from parallel connections queue behind each other,
    each answered later than the one before; the right secret is not delayed after them."""
    base_s, guesses = 0.02, 6
    served = serve(
        kinds=("tcp",), secret="s3cret-s3cret-s3cret", require_secret=True,
        auth_failure_delay_s=base_s,
    )  # fmt: skip
    refused: list[BaseException] = []

    def guess() -> None:
        raw = RawClient(served.url, timeout_s=10)
        reply = raw.handshake(proof=bytes(32))  # an attacker skips the server's proof
        raw.close()
        if reply.type is MessageType.ERROR:
            refused.append(AuthenticationError(unpack_error(reply.payload)[1]))

    started = time.monotonic()
    threads = [threading.Thread(target=guess) for _ in range(guesses)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join(timeout=30)
    elapsed = time.monotonic() - started
    assert len(refused) == guesses
    assert elapsed >= 0.9 * sum(base_s * 2**i for i in range(guesses))  # 1.26 s, not 0.02
    link = connect(served.url, secret="s3cret-s3cret-s3cret")
    _drive(link, 0, 0, 0)


def test_idle_and_surplus_connections_are_dropped_and_the_client_still_gets_in(
    serve: ServeFactory, connect: ConnectFactory
) -> None:
    """Slowloris and a socket flood: connections that never hand shake are dropped after
    the handshake timeout, those beyond the half-open cap at once; the client connects."""
    from ego.servers.socket.server import MAX_UNAUTHENTICATED

    served = serve(kinds=("tcp",), handshake_timeout_s=0.3)
    host, port = served.url.removeprefix("tcp://").rsplit(":", 1)
    idle = [socket.create_connection((host, int(port)), timeout=5) for _ in range(80)]
    try:
        assert wait_until(lambda: served.server.stats.dropped >= 80 - MAX_UNAUTHENTICATED)
        link = connect(served.url)  # the cap evicts the oldest idle one for it
        _drive(link, 0, 0, 0)
        assert wait_until(lambda: served.server.stats.dropped >= 80)
        for sock in idle:
            sock.settimeout(2.0)
            assert sock.recv(1) == b""  # the server hung up on every idle connection
        assert served.server.controller is not None  # but not on the client
        assert not served.server.peers.half_open
    finally:
        for sock in idle:
            sock.close()


def test_a_controller_that_only_sets_speeds_ends_once_the_deadman_stopped_its_robot(
    serve: ServeFactory, kind: str, caplog: pytest.LogCaptureFixture
) -> None:
    """Its steps send nothing (the speeds were confirmed once): only the heartbeat hears
    that the session ended. The controller must end as on a lost link (step() is -1),
    not step on with wheels it believes turning."""
    import ego

    served = serve(kinds=(kind,), deadline_s=DEADLINE_S)
    with ego.Robot(served.url, handle_signals=False) as robot:
        robot.motors.set_speed(250, 250)
        assert robot.step(32) == 0
        assert served.emu.world.speeds == (250, 250)
        assert wait_until(lambda: served.emu.world.speeds == (0, 0))  # hung in its own code
        assert served.server.stats.deadman_stops == 1
        with caplog.at_level(logging.ERROR):
            steps = [robot.step(32) for _ in range(3)]
            for _ in range(60):  # 2 s of steps at most
                if steps[-1] == -1:
                    break
                steps.append(robot.step(32))
    assert steps[-1] == -1, steps
    logged = [r.getMessage() for r in caplog.records if r.levelno >= logging.ERROR]
    assert any("the server's deadman stopped the robot" in m for m in logged), logged
    assert served.server.stats.sessions == 1  # it ended; it did not drive on in a new one


@pytest.mark.usefixtures("settled_heap")
def test_the_deadman_sleeps_until_the_deadline_instead_of_polling(
    serve: ServeFactory, connect: ConnectFactory
) -> None:
    """Issue 35: the deadman was a thread asking the session every 10 ms. Now it is a
    timer armed with the deadline: a silent controller's 0.5 s costs it a wake-up or two
    (one per deadline it was armed with), not fifty."""
    served = serve(kinds=("tcp",), deadline_s=DEADLINE_S)
    link = connect(served.url, heartbeat=False)
    _drive(link, 300, 300, 1)
    assert_deadman_fired(served.server, DEADLINE_S)
    deadman = served.server.deadman
    assert deadman is not None and deadman.fired <= 3, deadman.fired
