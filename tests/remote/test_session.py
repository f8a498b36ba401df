"""The sans-I/O server session, driven by hand with a fake clock: no sockets, no threads."""

from __future__ import annotations

import struct
import zlib
from collections.abc import Iterator

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ego.errors import AuthenticationError
from ego.net.auth import FailureThrottle
from ego.net.frames import (
    HEADER,
    MAGIC,
    PROTOCOL_VERSION,
    Frame,
    FrameKey,
    MessageType,
    decode_frame,
    encode_frame,
)
from ego.net.handshake import ClientHandshake
from ego.net.messages import Step, pack_step
from ego.net.payloads import pack_json, unpack_error, unpack_json
from ego.seam.batch import Request
from ego.seam.profile import Command
from ego.servers.sessions.actions import Action, Authenticated, Hangup, Peer, Run, Send, StopRobot
from ego.servers.sessions.session import Session

SECRET = b"s3cret-s3cret-s3cret"
TCP = Peer(("tcp", 1, None), "tcp client", "127.0.0.1")
OTHER = Peer(("tcp", 2, None), "tcp other", "127.0.0.1")
UDP = Peer(("udp", 0, ("127.0.0.1", 5000)), "udp 127.0.0.1:5000", "127.0.0.1", 16384)
SPEEDS = Step((Request(Command.SET_SPEED, (200, 200)), Request(Command.GET_SPEED)))


def session(secret: bytes | None = SECRET, **options: object) -> Session:
    return Session(
        secret=secret,
        deadline_s=0.5,
        chunk_size=16384,
        welcome=lambda: {"firmware": "webots"},
        throttle=FailureThrottle(base_s=0.2),
        **options,  # type: ignore[arg-type]
    )


def sends(actions: list[Action]) -> list[Frame]:
    return [decode_frame(a.data) for a in actions if isinstance(a, Send)]


class Client:
    """The client's half, by hand: frames sealed once the handshake gave a key."""

    def __init__(self, server: Session, peer: Peer = TCP, secret: bytes | None = SECRET) -> None:
        self.server, self.peer, self.secret = server, peer, secret
        self.seq, self.sid = 0, 0
        self.key: FrameKey | None = None

    def frame(self, mtype: MessageType, payload: bytes = b"", seq: int | None = None) -> Frame:
        self.seq = self.seq + 1 if seq is None else seq
        return Frame(mtype, self.seq, payload, self.sid)

    def feed(self, frame: Frame, now: float = 0.0) -> list[Action]:
        data = encode_frame(frame.type, frame.seq, frame.payload, frame.session, self.key)
        if self.peer.datagram is not None:
            return self.server.datagram(self.peer, data, now)
        opened = decode_frame(data, self.server.key_for(frame.session))
        return self.server.receive(self.peer, opened, now)

    def opened(self, action: Action) -> Frame:
        assert isinstance(action, Send)
        return decode_frame(action.data, self.key)

    def hello(self, shake: ClientHandshake) -> Frame:
        """HELLO, padded as a UDP client pads it (no reply may be bigger)."""
        return self.frame(
            MessageType.HELLO, pack_json({**unpack_json(shake.hello()), "pad": "-" * 400})
        )

    def connect(self, now: float = 0.0) -> Frame:
        shake = ClientHandshake(self.secret, "test")
        (reply,) = self.feed(self.hello(shake), now)
        challenge = self.opened(reply)
        if challenge.type is MessageType.COOKIE:
            shake.take_cookie(challenge.payload)
            (reply,) = self.feed(self.hello(shake), now)
            challenge = self.opened(reply)
        self.sid = challenge.session
        proof = shake.answer(challenge.payload, self.sid)
        actions = self.feed(self.frame(MessageType.AUTH, proof), now)
        self.key = shake.key
        return self.opened(actions[-1])


@pytest.fixture
def controlled() -> Iterator[tuple[Session, Client]]:
    server = session()
    client = Client(server)
    assert client.connect().type is MessageType.OK
    yield server, client


def test_a_proven_client_takes_control_and_its_step_is_run(
    controlled: tuple[Session, Client],
) -> None:
    server, client = controlled
    assert server.controller == TCP
    (run,) = client.feed(client.frame(MessageType.STEP, pack_step(SPEEDS.requests)))
    assert isinstance(run, Run) and run.call == SPEEDS
    (send,) = server.completed(run.session, run.seq, b"\x01\x02\x03\x04", 0.1)
    reply = client.opened(send)
    assert (reply.type, reply.payload, reply.seq) == (MessageType.OK, b"\x01\x02\x03\x04", run.seq)


def test_the_welcome_is_sealed_and_names_the_firmware_and_deadline() -> None:
    server = session()
    client = Client(server)
    welcome = unpack_json(client.connect().payload)
    assert welcome == {"firmware": "webots", "deadline_s": 0.5, "chunk_size": 16384}
    with pytest.raises(Exception, match="sealed"):
        decode_frame(server.shutdown()[1].data)  # type: ignore[union-attr]


def test_a_repeated_request_is_answered_from_the_cache_and_never_runs_twice(
    controlled: tuple[Session, Client],
) -> None:
    server, client = controlled
    step = client.frame(MessageType.STEP, pack_step(SPEEDS.requests))
    (run,) = client.feed(step)
    assert isinstance(run, Run)
    (working,) = client.feed(step)
    assert client.opened(working).type is MessageType.WORKING
    (first,) = server.completed(run.session, run.seq, b"reply", 0.1)
    (again,) = client.feed(step, 0.2)
    assert isinstance(again, Send) and isinstance(first, Send) and again.data == first.data
    assert server.stats.repeats == 1


def test_the_deadman_stops_the_robot_after_silence_and_only_new_requests_count(
    controlled: tuple[Session, Client],
) -> None:
    server, client = controlled
    ping = client.frame(MessageType.PING)
    (run,) = client.feed(ping, 0.3)
    assert isinstance(run, Run)
    server.completed(run.session, run.seq, b"", 0.3)
    for t in (0.5, 0.7, 0.79):
        client.feed(ping, t)  # a replayed or repeated frame keeps nothing alive
        assert server.tick(t) == []
    actions = server.tick(0.81)
    assert isinstance(actions[0], StopRobot) and "silent for 510 ms" in actions[0].reason
    assert isinstance(actions[-1], Hangup)
    assert server.controller is None and server.stats.deadman_stops == 1


def test_a_running_request_holds_the_deadman_off(controlled: tuple[Session, Client]) -> None:
    server, client = controlled
    (run,) = client.feed(client.frame(MessageType.STEP, pack_step(SPEEDS.requests)), 0.0)
    assert server.tick(5.0) == []  # the serial line may be retrying: not a dead client
    assert isinstance(run, Run)
    server.completed(run.session, run.seq, b"", 5.0)
    assert server.tick(5.4) == []
    assert isinstance(server.tick(5.6)[0], StopRobot)


def test_goodbye_stops_the_robot_before_the_reply(controlled: tuple[Session, Client]) -> None:
    _, client = controlled
    stop, send = client.feed(client.frame(MessageType.BYE))
    assert isinstance(stop, StopRobot) and client.opened(send).type is MessageType.OK
    client.key = None  # the session and its key are gone
    (refused,) = client.feed(client.frame(MessageType.PING))
    assert "said goodbye" in unpack_error(decode_frame(refused.data).payload)[1]  # type: ignore[union-attr]


def test_a_lost_connection_stops_the_robot(controlled: tuple[Session, Client]) -> None:
    server, _ = controlled
    (stop,) = server.peer_lost(TCP)
    assert isinstance(stop, StopRobot) and "disconnected" in stop.reason


def test_a_second_client_is_told_the_robot_is_busy(controlled: tuple[Session, Client]) -> None:
    server, _ = controlled
    (reply,) = Client(server, OTHER).feed(
        Frame(MessageType.HELLO, 1, ClientHandshake(SECRET, "x").hello())
    )
    name, message, _ = unpack_error(decode_frame(reply.data).payload)  # type: ignore[union-attr]
    assert name == "RobotBusyError" and "another client" in message


def test_a_wrong_proof_is_answered_late_and_hung_up_on() -> None:
    server = session()
    client = Client(server)
    shake = ClientHandshake(SECRET, "x")
    (reply,) = client.feed(client.frame(MessageType.HELLO, shake.hello()))
    client.sid = decode_frame(reply.data).session  # type: ignore[union-attr]
    wrong = pack_json({"proof": bytes(32).hex()})
    send, hangup = client.feed(client.frame(MessageType.AUTH, wrong), 10.0)
    assert isinstance(send, Send) and send.delay_s == pytest.approx(0.2)
    assert isinstance(hangup, Hangup) and hangup.delay_s == send.delay_s
    assert "wrong shared secret" in unpack_error(decode_frame(send.data).payload)[1]
    assert server.controller is None and server.stats.refused == 1


def test_a_client_refuses_a_server_that_cannot_prove_the_secret() -> None:
    impostor = session(secret=None)  # says "no secret needed"
    client = Client(impostor)
    with pytest.raises(AuthenticationError, match="could not prove"):
        client.connect()
    assert impostor.controller is None  # and it never got a proof


def test_a_udp_hello_gets_a_cookie_first_and_no_state_is_kept() -> None:
    server = session()
    shake = ClientHandshake(SECRET, "x")
    hello = pack_json({**unpack_json(shake.hello()), "pad": "-" * 400})
    data = encode_frame(MessageType.HELLO, 1, hello)
    (reply,) = server.datagram(UDP, data, 0.0)
    assert isinstance(reply, Send) and len(reply.data) <= len(data)  # no amplification
    assert decode_frame(reply.data).type is MessageType.COOKIE
    assert not server.gate._pending  # stateless until the client proves its address
    assert server.stats.cookies == 1


def test_a_forged_udp_hello_never_gets_a_bigger_answer() -> None:
    server = session()
    hello = encode_frame(MessageType.HELLO, 1, pack_json({"nonce": bytes(32).hex()}))
    (cookie,) = server.datagram(UDP, hello, 0.0)
    assert isinstance(cookie, Send) and len(cookie.data) <= len(hello)
    tiny = encode_frame(MessageType.HELLO, 1, b"{}")  # malformed: its error would be bigger
    assert server.datagram(UDP, tiny, 0.0) == []


def test_a_udp_client_completes_the_handshake_with_its_cookie() -> None:
    server = session()
    client = Client(server, UDP)
    assert client.connect().type is MessageType.OK
    assert server.controller == UDP


def test_forged_and_unsealed_datagrams_of_a_sealed_session_are_dropped() -> None:
    server = session()
    client = Client(server, UDP)
    client.connect()
    step = pack_step((Request(Command.SET_SPEED, (-900, 900)),))
    unsealed = encode_frame(MessageType.STEP, 99, step, client.sid)
    wrong_key = encode_frame(
        MessageType.STEP, 99, step, client.sid, FrameKey(bytes(32), server=False)
    )
    assert server.datagram(UDP, unsealed, 0.1) == []
    assert server.datagram(UDP, wrong_key, 0.1) == []
    assert server.stats.forged == 2 and server.stats.steps == 0


def test_authenticated_peer_gets_its_key() -> None:
    server = session()
    client = Client(server)
    shake = ClientHandshake(SECRET, "x")
    (reply,) = client.feed(client.frame(MessageType.HELLO, shake.hello()))
    client.sid = decode_frame(reply.data).session  # type: ignore[union-attr]
    proof = shake.answer(decode_frame(reply.data).payload, client.sid)  # type: ignore[union-attr]
    authenticated, _ = client.feed(client.frame(MessageType.AUTH, proof))
    assert isinstance(authenticated, Authenticated) and authenticated.key is not None


# -- issue 22: one request in flight, no amplification, the end told -------------------------


def test_a_request_sent_while_another_runs_is_refused_not_queued(
    controlled: tuple[Session, Client],
) -> None:
    server, client = controlled
    (run,) = client.feed(client.frame(MessageType.STEP, pack_step(SPEEDS.requests)))
    assert isinstance(run, Run)
    for _ in range(3):  # pipelined: none of them becomes a Run
        (refused,) = client.feed(client.frame(MessageType.STEP, pack_step(SPEEDS.requests)))
        name, message, _ = unpack_error(client.opened(refused).payload)
        assert name == "FrameError" and f"while request {run.seq} was still running" in message
    assert server.stats.pipelined == 3 and server.stats.steps == 1
    server.completed(run.session, run.seq, b"", 0.1)
    (after,) = client.feed(client.frame(MessageType.STEP, pack_step(SPEEDS.requests)), 0.2)
    assert isinstance(after, Run)  # answered: the next one runs


def test_a_goodbye_while_a_request_runs_stops_the_robot_and_the_run_is_no_longer_live(
    controlled: tuple[Session, Client],
) -> None:
    server, client = controlled
    (run,) = client.feed(client.frame(MessageType.STEP, pack_step(SPEEDS.requests)))
    assert isinstance(run, Run) and server.live(run.session)
    stop, _ = client.feed(client.frame(MessageType.BYE))
    assert isinstance(stop, StopRobot)
    assert not server.live(run.session)  # the adapter drops the Run if not yet started
    assert server.completed(run.session, run.seq, b"", 0.1) == []


def test_a_stranger_is_never_answered_with_more_than_it_sent() -> None:
    server = session(secret=None)
    controller = Client(server, UDP, secret=None)
    controller.connect()
    stranger = Peer(("udp", 0, ("127.0.0.1", 6000)), "udp 127.0.0.1:6000", "127.0.0.1", 16384)
    for mtype in (MessageType.AUTH, MessageType.STEP, MessageType.PING, MessageType.BYE):
        for session_id in (0, 77, controller.sid):
            data = encode_frame(mtype, 1, b"", session_id)
            for action in server.datagram(stranger, data, 0.0):
                assert isinstance(action, Send) and len(action.data) <= len(data), mtype


def test_the_deadman_tells_its_client_the_session_ended_and_why() -> None:
    server = session()
    client = Client(server, UDP)
    client.connect()
    *_, told, _ = server.tick(1.0)
    frame = client.opened(told)
    name, message, fields = unpack_error(frame.payload)
    assert (frame.type, frame.seq, name) == (MessageType.ERROR, 0, "LinkLostError")
    assert message.startswith("session ended: the server's deadman stopped the robot")
    assert fields == {"session_ended": True}
    client.key = None
    late = encode_frame(MessageType.PING, 9, b"", client.sid)  # 20 bytes: from its own address
    (reply,) = server.datagram(UDP, late, 1.1)
    assert "deadman" in unpack_error(decode_frame(reply.data).payload)[1]  # type: ignore[union-attr]
    stranger = Peer(("udp", 0, ("127.0.0.1", 6000)), "udp 127.0.0.1:6000", "127.0.0.1", 16384)
    assert server.datagram(stranger, late, 1.1) == []  # elsewhere: too big an answer


STRANGER = Peer(("udp", 0, ("127.0.0.1", 6000)), "udp 127.0.0.1:6000", "127.0.0.1", 16384)


@st.composite
def _any_frame(draw: st.DrawFn) -> tuple[int, int, bytes]:
    """(type byte, which session, payload) of a frame with a good CRC."""
    type_ = draw(st.sampled_from([*MessageType, 0x3F]) | st.integers(0, 255))
    return int(type_), draw(st.integers(0, 3)), draw(st.binary(max_size=64))


@settings(max_examples=300, deadline=None)
@given(frames=st.lists(_any_frame(), min_size=1, max_size=10), cut=st.integers(0, 40))
def test_no_datagram_of_a_stranger_gets_a_bigger_answer(
    frames: list[tuple[int, int, bytes]], cut: int
) -> None:
    server = session(secret=None)
    gone = Client(server, UDP, secret=None)
    gone.connect()
    gone.feed(gone.frame(MessageType.BYE))  # an ended session
    controller = Client(server, UDP, secret=None)
    controller.connect()
    sessions = (0, controller.sid, gone.sid, 0x1234)
    for type_, pick, payload in frames:
        head = HEADER.pack(MAGIC, PROTOCOL_VERSION, type_, sessions[pick], 1, len(payload))
        data = head + payload + struct.pack("<I", zlib.crc32(head + payload))
        for sent in (data, data[: max(1, len(data) - cut)]):
            for action in server.datagram(STRANGER, sent, 0.2):
                assert isinstance(action, Send) and len(action.data) <= len(sent), (type_, pick)
    assert server.controller == UDP  # and the controller kept the robot
