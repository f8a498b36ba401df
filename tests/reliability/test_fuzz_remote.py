"""The remote wire fed random and mutated input: a typed error or a value, never a hang.

Fuzzed here: frames, the stream reader, the payloads, URLs, sealed (authenticated)
frames and the server session fed any datagrams. Each property says which errors are
allowed (ego's typed errors, and the builtin a docstring promises); anything else fails,
and so does an example slower than the deadline (a hang). The shared settings:
``fuzzing.py``.
"""

from __future__ import annotations

from collections.abc import Callable

import pytest
from fuzzing import COMMAND_BYTES, FUZZ, MUTATIONS, PROFILE_LIST, U32, mutated
from hypothesis import given
from hypothesis import strategies as st

import ego
from ego.backends.remote.channel import error_from_reply
from ego.errors import (
    FrameError,
)
from ego.net.frames import (
    HEADER,
    MAGIC,
    MAX_PAYLOAD,
    OVERHEAD,
    PROTOCOL_VERSION,
    Frame,
    FrameKey,
    FrameReader,
    MessageType,
    decode_frame,
    encode_frame,
)
from ego.net.messages import pack_step, unpack_step
from ego.net.payloads import (
    ASCII_REPLY_LINES,
    pack_ascii,
    pack_fetch,
    pack_json,
    pack_part,
    unpack_ascii,
    unpack_error,
    unpack_fetch,
    unpack_json,
    unpack_part,
)
from ego.net.urls import parse_url
from ego.seam.profile import Command
from ego.serial.protocol import encode_batch

# -- the remote wire ------------------------------------------------------------------------

FRAMES = st.builds(
    encode_frame, st.sampled_from(list(MessageType)), U32, st.binary(max_size=300), U32
)


def check_frame(data: bytes) -> None:
    """``decode_frame(data)``: a frame with every field in range, or FrameError."""
    try:
        frame = decode_frame(data)
    except FrameError:
        return
    assert frame.type in set(MessageType)
    assert 0 <= frame.seq < 2**32 and 0 <= frame.session < 2**32
    assert len(frame.payload) <= MAX_PAYLOAD
    assert len(data) == OVERHEAD + len(frame.payload)


@FUZZ
@given(data=st.binary(max_size=120))
def test_random_bytes_are_no_frame(data: bytes) -> None:
    check_frame(data)


@FUZZ
@given(
    head=st.tuples(
        st.sampled_from([MAGIC, b"GE"]),
        st.sampled_from([PROTOCOL_VERSION, PROTOCOL_VERSION + 1, 0]),
        st.integers(0, 255),
        U32,
        U32,
        st.one_of(st.integers(0, 64), st.integers(MAX_PAYLOAD - 1, 2**32 - 1)),
    ),
    rest=st.binary(max_size=80),
)
def test_a_plausible_header_over_random_bytes_is_a_frame_or_frame_error(
    head: tuple[bytes, int, int, int, int, int], rest: bytes
) -> None:
    check_frame(HEADER.pack(*head) + rest)


@FUZZ
@given(frame=FRAMES, ops=MUTATIONS)
def test_a_mutated_frame_is_refused_or_intact(
    frame: bytes, ops: list[tuple[int, int, int]]
) -> None:
    check_frame(mutated(frame, ops))


@FUZZ
@given(
    pieces=st.lists(st.one_of(FRAMES, st.binary(max_size=40)), min_size=1, max_size=6),
    cuts=st.lists(st.integers(1, 200), max_size=20),
)
def test_the_stream_reader_gives_frames_or_stays_broken_and_bounded(
    pieces: list[bytes], cuts: list[int]
) -> None:
    stream = b"".join(pieces)
    reader = FrameReader()
    broken = False
    position = 0
    for cut in [*cuts, len(stream)]:
        chunk, position = stream[position : position + cut], position + cut
        try:
            frames = reader.feed(chunk)
        except FrameError:
            broken = True
            continue
        assert not broken, "a reader fed on after a bad frame"
        assert all(f.type in set(MessageType) for f in frames)
        assert reader.buffered < OVERHEAD + MAX_PAYLOAD
        if position >= len(stream):
            break


PAYLOAD_PARSERS: list[tuple[str, Callable[[bytes], object]]] = [
    ("json", unpack_json),
    ("ascii", unpack_ascii),
    ("part", unpack_part),
    ("fetch", unpack_fetch),
]
VALID_PAYLOADS = [
    pack_json({"nonce": "00" * 32, "auth": True}),
    pack_ascii("V", 2),
    pack_part(MessageType.OK, 10, 4, b"abcdef"),
    pack_fetch(7, 16384),
]


@pytest.mark.parametrize(("name", "parser"), PAYLOAD_PARSERS, ids=[n for n, _ in PAYLOAD_PARSERS])
@FUZZ
@given(
    payload=st.one_of(
        st.binary(max_size=64),
        st.tuples(st.sampled_from(VALID_PAYLOADS), MUTATIONS).map(lambda pm: mutated(*pm)),
    )
)
def test_a_payload_parser_gives_a_valid_value_or_frame_error(
    name: str, parser: Callable[[bytes], object], payload: bytes
) -> None:
    try:
        value = parser(payload)
    except FrameError:
        return
    if name == "json":
        assert isinstance(value, dict)
    elif name == "ascii":
        letter, lines = value  # type: ignore[misc]
        assert ASCII_REPLY_LINES[letter] == lines
    elif name == "part":
        kind, total, offset, data = value  # type: ignore[misc]
        assert kind in (MessageType.OK, MessageType.ERROR)
        assert offset + len(data) <= total <= MAX_PAYLOAD
    else:
        seq, offset = value  # type: ignore[misc]
        assert 0 <= seq < 2**32 and 0 <= offset < 2**32


@FUZZ
@given(payload=st.binary(max_size=64))
def test_an_error_payload_always_names_a_class_and_a_message(payload: bytes) -> None:
    name, message, fields = unpack_error(payload)
    assert isinstance(name, str) and isinstance(message, str) and isinstance(fields, dict)
    error = error_from_reply(payload, "fuzz")  # never a TypeError, whatever the class
    assert isinstance(error, ego.errors.EgoError)


@FUZZ
@given(
    url=st.one_of(
        st.text(max_size=40),
        st.tuples(
            st.sampled_from(["tcp://", "udp://", "http://", ""]),
            st.text(max_size=15),
            st.sampled_from(["", ":", ":0", ":4242", ":65536", ":99999", ":x"]),
        ).map("".join),
    )
)
def test_a_url_gives_a_scheme_host_and_port_or_value_error(url: str) -> None:
    try:
        scheme, host, port = parse_url(url)
    except ValueError as exc:
        assert type(exc) is ValueError
        return
    assert scheme in ("tcp", "udp") and host and 0 <= port <= 65535


# -- the authenticated frames and the server session -----------------------------------------

KEY = b"k" * 32


@FUZZ
@given(frame=FRAMES, ops=MUTATIONS, session=U32)
def test_a_mutated_sealed_frame_is_refused_or_exactly_the_one_sealed(
    frame: bytes, ops: list[tuple[int, int, int]], session: int
) -> None:
    """No change to a sealed frame passes its MAC: opened, it is the frame as sealed."""
    original = decode_frame(frame)
    sealed = encode_frame(
        original.type, original.seq, original.payload, session, FrameKey(KEY, server=False)
    )
    data = mutated(sealed, ops)
    try:
        opened = decode_frame(data, FrameKey(KEY, server=True))
    except FrameError:
        return
    assert data == sealed
    assert opened == Frame(original.type, original.seq, original.payload, session)


@FUZZ
@given(frame=FRAMES)
def test_a_sealed_frame_cannot_be_reflected_back_to_its_sender(frame: bytes) -> None:
    original = decode_frame(frame)
    key = FrameKey(KEY, server=False)
    sealed = encode_frame(original.type, original.seq, original.payload, 7, key)
    with pytest.raises(FrameError):
        decode_frame(sealed, key)  # the client's own frame, sent back to it


@FUZZ
@given(
    payload=st.one_of(
        st.binary(max_size=80),
        st.tuples(
            st.lists(
                st.tuples(
                    st.sampled_from(COMMAND_BYTES),
                    st.lists(st.integers(-(2**31), 2**31 - 1), max_size=3),
                ),
                max_size=6,
            ).map(
                lambda rs: b"".join(
                    bytes([c, len(a)]) + b"".join(v.to_bytes(4, "little", signed=True) for v in a)
                    for c, a in rs
                )
            ),
            MUTATIONS,
        ).map(lambda pm: mutated(*pm)),
    )
)
def test_a_step_payload_gives_requests_the_server_can_encode_or_a_typed_refusal(
    payload: bytes,
) -> None:
    try:
        requests = unpack_step(payload)
    except FrameError:
        return
    assert requests and all(r.command is not Command.END for r in requests)
    assert pack_step(requests) == payload
    for profile in PROFILE_LIST:  # what the server does next: refused, or their batch
        try:
            batch = encode_batch(requests, profile)
        except (ValueError, ego.errors.UnsupportedDeviceError):
            continue
        assert batch.tx[0] == requests[0].command and batch.tx[-1] == 0


@FUZZ
@given(datagrams=st.lists(st.one_of(FRAMES, st.binary(max_size=60)), max_size=12), data=st.data())
def test_the_session_fed_any_datagrams_runs_nothing_for_a_stranger(
    datagrams: list[bytes], data: st.DataObject
) -> None:
    """Random and mutated datagrams from a peer that never proved the secret: the session
    answers or drops them, and never runs anything on the robot."""
    from ego.servers.sessions.actions import Peer, Run, StopRobot
    from ego.servers.sessions.session import Session

    session = Session(secret=b"s" * 16, deadline_s=0.5, chunk_size=16384, welcome=dict)
    peer = Peer(("udp", 0, ("10.0.0.1", 9)), "udp stranger", "10.0.0.1", 16384)
    for datagram in datagrams:
        ops = data.draw(MUTATIONS)
        actions = session.datagram(peer, mutated(datagram, ops), 0.0)
        actions += session.receive(peer, decode_frame(datagram), 0.0) if _is_frame(datagram) else []
        assert not any(isinstance(a, Run | StopRobot) for a in actions)
    assert session.controller is None


def _is_frame(data: bytes) -> bool:
    try:
        decode_frame(data)
    except FrameError:
        return False
    return True
