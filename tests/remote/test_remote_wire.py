"""The remote wire format and handshake on bytes alone: frames, sequence numbers, slices, MACs."""

from __future__ import annotations

import os
import random

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ego.backends.remote.channel import error_from_reply
from ego.errors import (
    ConfigSyntaxError,
    FrameError,
    InsecureSecretError,
    PortBusyError,
    VersionMismatchError,
)
from ego.net.auth import (
    check_proof,
    client_proof,
    coerce_secret,
    is_loopback,
    load_secret,
    new_nonce,
    new_secret,
    server_proof,
    write_secret,
)
from ego.net.frames import (
    HEADER,
    MAGIC,
    MAX_PAYLOAD,
    OVERHEAD,
    PROTOCOL_VERSION,
    FrameReader,
    MessageType,
    decode_frame,
    encode_frame,
)
from ego.net.payloads import (
    error_fields,
    pack_ascii,
    pack_error,
    pack_fetch,
    split_reply,
    unpack_ascii,
    unpack_error,
    unpack_fetch,
    unpack_json,
    unpack_part,
)
from ego.net.sequence import SequenceGuard, Verdict, next_seq, seq_after
from ego.net.urls import parse_url

U32 = st.integers(0, 2**32 - 1)


@given(st.sampled_from(list(MessageType)), U32, U32, st.binary(max_size=2000))
def test_frame_round_trips(mtype: MessageType, seq: int, session: int, payload: bytes) -> None:
    frame = decode_frame(encode_frame(mtype, seq, payload, session))
    assert (frame.type, frame.seq, frame.session, frame.payload) == (mtype, seq, session, payload)


def test_frame_layout_is_magic_version_type_session_seq_length_payload_crc() -> None:
    data = encode_frame(MessageType.STEP, 7, b"\xb2\x00", session=0x01020304)
    assert data[:2] == MAGIC
    assert data[2] == PROTOCOL_VERSION
    assert data[3] == MessageType.STEP
    assert data[4:8] == bytes([4, 3, 2, 1])
    assert data[8:12] == (7).to_bytes(4, "little")
    assert data[12:16] == (2).to_bytes(4, "little")
    assert data[16:18] == b"\xb2\x00"
    assert len(data) == OVERHEAD + 2


def test_every_single_bit_flip_is_detected() -> None:
    data = encode_frame(MessageType.OK, 3, b"\x01\x02\x03\x04reply", session=9)
    for bit in range(len(data) * 8):
        flipped = bytearray(data)
        flipped[bit // 8] ^= 1 << (bit % 8)
        with pytest.raises(FrameError):
            decode_frame(bytes(flipped))


@pytest.mark.parametrize("cut", [0, 1, OVERHEAD - 1, OVERHEAD + 2])
def test_truncated_frame_is_refused(cut: int) -> None:
    data = encode_frame(MessageType.STEP, 1, b"abcdef")
    with pytest.raises(FrameError):
        decode_frame(data[:cut])


def test_frame_with_bytes_after_it_is_refused() -> None:
    with pytest.raises(FrameError, match="announces"):
        decode_frame(encode_frame(MessageType.STEP, 1, b"ab") + b"x")


def test_wrong_magic_is_refused() -> None:
    data = bytearray(encode_frame(MessageType.PING, 1))
    data[0:2] = b"XX"
    with pytest.raises(FrameError, match="magic"):
        decode_frame(bytes(data))


def test_unknown_message_type_is_refused() -> None:
    head = HEADER.pack(MAGIC, PROTOCOL_VERSION, 100, 0, 1, 0)
    import zlib

    data = head + zlib.crc32(head).to_bytes(4, "little")
    with pytest.raises(FrameError, match="unknown message type 100"):
        decode_frame(data)


def test_payload_over_the_limit_cannot_be_encoded() -> None:
    with pytest.raises(ValueError, match="exceeds"):
        encode_frame(MessageType.OK, 1, bytes(MAX_PAYLOAD + 1))
    assert len(encode_frame(MessageType.OK, 1, bytes(MAX_PAYLOAD))) == MAX_PAYLOAD + OVERHEAD


def test_oversized_length_is_refused_from_the_header_alone() -> None:
    reader = FrameReader()
    head = HEADER.pack(MAGIC, PROTOCOL_VERSION, MessageType.STEP, 0, 1, MAX_PAYLOAD + 1)
    with pytest.raises(FrameError, match="exceeds"):
        reader.feed(head)  # refused before a byte of the payload is buffered
    assert reader.buffered == 0


def test_other_protocol_version_is_named_in_the_error() -> None:
    head = HEADER.pack(MAGIC, PROTOCOL_VERSION + 1, MessageType.HELLO, 0, 5, 0)
    import zlib

    data = head + zlib.crc32(head).to_bytes(4, "little")
    with pytest.raises(VersionMismatchError, match=f"version {PROTOCOL_VERSION + 1}") as info:
        decode_frame(data)
    assert (info.value.peer_version, info.value.seq) == (PROTOCOL_VERSION + 1, 5)


@given(st.lists(st.binary(max_size=300), min_size=1, max_size=8), st.randoms())
def test_stream_reader_reassembles_frames_cut_anywhere(
    payloads: list[bytes], rnd: random.Random
) -> None:
    stream = b"".join(encode_frame(MessageType.OK, i + 1, p) for i, p in enumerate(payloads))
    reader = FrameReader()
    got = []
    pos = 0
    while pos < len(stream):
        step = rnd.randint(1, 64)
        got += reader.feed(stream[pos : pos + step])
        pos += step
    assert [f.payload for f in got] == payloads
    assert [f.seq for f in got] == list(range(1, len(payloads) + 1))
    assert reader.buffered == 0


def test_stream_reader_stays_broken_after_a_bad_frame() -> None:
    reader = FrameReader()
    with pytest.raises(FrameError):
        reader.feed(b"garbage that is long enough")
    with pytest.raises(FrameError):
        reader.feed(encode_frame(MessageType.PING, 1))


# -- sequence numbers ------------------------------------------------------------------


def test_sequence_numbers_wrap_without_zero() -> None:
    assert next_seq(1) == 2
    assert next_seq(2**32 - 1) == 1
    assert next_seq(0) == 1


def test_sequence_order_survives_the_wrap() -> None:
    assert seq_after(2, 1)
    assert not seq_after(1, 2)
    assert not seq_after(5, 5)
    assert seq_after(1, 2**32 - 1)
    assert not seq_after(2**32 - 1, 1)


def test_guard_answers_a_repeat_from_its_cache_and_ignores_older() -> None:
    guard = SequenceGuard()
    assert guard.check(1) is Verdict.NEW
    guard.begin(1)
    assert guard.check(1) is Verdict.WORKING
    guard.done(1, b"one")
    assert guard.check(1) is Verdict.REPEAT
    assert guard.cached == b"one"
    assert guard.check(2) is Verdict.NEW
    guard.begin(2)
    guard.done(2, b"two")
    assert guard.check(1) is Verdict.STALE
    assert guard.check(2) is Verdict.REPEAT
    assert guard.cached == b"two"


@settings(max_examples=200)
@given(st.lists(st.integers(1, 40), max_size=200))
def test_guard_runs_each_request_at_most_once_in_order(arrivals: list[int]) -> None:
    """Whatever order duplicates and late datagrams come in, nothing runs twice or backwards."""
    guard = SequenceGuard()
    ran: list[int] = []
    for seq in arrivals:
        if guard.check(seq) is Verdict.NEW:
            guard.begin(seq)
            ran.append(seq)
            guard.done(seq, str(seq).encode())
        elif guard.check(seq) is Verdict.REPEAT:
            assert guard.cached == str(seq).encode()  # the reply of that very request
    assert ran == sorted(set(ran))


# -- payloads --------------------------------------------------------------------------


def test_big_reply_slices_cover_it_exactly() -> None:
    payload = os.urandom(50_000)
    chunk = 4096
    got = bytearray()
    while len(got) < len(payload):
        part = split_reply(MessageType.OK, payload, len(got), chunk)
        assert OVERHEAD + len(part) <= chunk
        kind, total, offset, data = unpack_part(part)
        assert (kind, total, offset) == (MessageType.OK, len(payload), len(got))
        got += data
    assert bytes(got) == payload


@pytest.mark.parametrize(
    "part",
    [
        b"\x40\x00\x00",  # shorter than its header
        bytes([MessageType.STEP, 0, 0, 0]) + (10).to_bytes(4, "little") + bytes(4) + b"x",
        bytes([MessageType.OK, 0, 0, 0])
        + (10).to_bytes(4, "little")
        + (8).to_bytes(4, "little")
        + b"xyz",  # runs past its total
        bytes([MessageType.OK, 0, 0, 0]) + (2**31).to_bytes(4, "little") + bytes(4) + b"x",
    ],
)
def test_inconsistent_slice_is_refused(part: bytes) -> None:
    with pytest.raises(FrameError):
        unpack_part(part)


def test_fetch_round_trips_and_refuses_wrong_size() -> None:
    assert unpack_fetch(pack_fetch(12, 34)) == (12, 34)
    with pytest.raises(FrameError):
        unpack_fetch(b"\x00")


def test_ascii_request_names_relayed_letters_only() -> None:
    assert unpack_ascii(pack_ascii("V", 2)) == ("V", 2)
    with pytest.raises(FrameError, match="'R'"):
        unpack_ascii(pack_ascii("R", 1))
    with pytest.raises(FrameError):
        unpack_ascii(pack_ascii("V", 1))  # V answers two lines


def test_error_payload_round_trips_and_garbage_becomes_remote_error() -> None:
    assert unpack_error(pack_error("LinkTimeoutError", "3 of 16 bytes")) == (
        "LinkTimeoutError",
        "3 of 16 bytes",
        {},
    )
    assert unpack_error(b"\xff\xfe")[0] == "RemoteError"


@pytest.mark.parametrize("payload", [b"[1, 2]", b"{", b"\xff"])
def test_json_payload_must_be_an_object(payload: bytes) -> None:
    with pytest.raises(FrameError):
        unpack_json(payload)


@pytest.mark.parametrize(
    ("url", "expected"),
    [
        ("tcp://robot:4242", ("tcp", "robot", 4242)),
        ("udp://127.0.0.1:0", ("udp", "127.0.0.1", 0)),
        ("tcp://robot", ("tcp", "robot", 4242)),
        ("udp://[::1]:9000", ("udp", "::1", 9000)),
    ],
)
def test_url_gives_scheme_host_port(url: str, expected: tuple[str, str, int]) -> None:
    assert parse_url(url) == expected


@pytest.mark.parametrize("url", ["socket://robot:1", "tcp://", "tcp://robot:99999", "robot:4242"])
def test_bad_url_is_refused(url: str) -> None:
    with pytest.raises(ValueError):
        parse_url(url)


# -- handshake -------------------------------------------------------------------------


def test_proofs_depend_on_secret_nonces_session_and_direction() -> None:
    server_nonce, client_nonce = new_nonce(), new_nonce()
    proof = client_proof(b"secret", server_nonce, client_nonce, 7)
    assert check_proof(proof, client_proof(b"secret", server_nonce, client_nonce, 7))
    assert not check_proof(proof, client_proof(b"Secret", server_nonce, client_nonce, 7))
    assert not check_proof(proof, client_proof(b"secret", new_nonce(), client_nonce, 7))
    assert not check_proof(proof, client_proof(b"secret", server_nonce, client_nonce, 8))
    # A server's proof can never be replayed as a client's.
    assert not check_proof(proof, server_proof(b"secret", server_nonce, client_nonce, 7))
    assert b"secret" not in proof


def test_nonces_are_fresh() -> None:
    assert len({new_nonce() for _ in range(100)}) == 100


@pytest.mark.parametrize(
    ("host", "loopback"),
    [
        ("127.0.0.1", True),
        ("127.1.2.3", True),
        ("::1", True),
        ("localhost", True),
        ("0.0.0.0", False),
        ("192.168.1.5", False),
        ("robot.local", False),
    ],
)
def test_loopback_addresses_are_told_apart(host: str, loopback: bool) -> None:
    assert is_loopback(host) is loopback


def test_secret_file_is_read_without_its_newline(tmp_path: os.PathLike[str]) -> None:
    path = os.path.join(tmp_path, "secret")
    with open(path, "w") as f:
        f.write("s3cret-s3cret-s3cret\n")
    os.chmod(path, 0o600)
    assert load_secret(path) == b"s3cret-s3cret-s3cret"


def test_empty_secret_file_is_refused(tmp_path: os.PathLike[str]) -> None:
    path = os.path.join(tmp_path, "secret")
    with open(path, "w") as f:
        f.write("\n")
    os.chmod(path, 0o600)
    with pytest.raises(ValueError, match="empty"):
        load_secret(path)


@pytest.mark.parametrize("mode", [0o640, 0o604, 0o620, 0o660])
def test_a_secret_file_others_may_touch_is_refused_as_ssh_does(
    tmp_path: os.PathLike[str], mode: int
) -> None:
    path = os.path.join(tmp_path, "secret")
    with open(path, "w") as f:
        f.write("a-secret-long-enough-to-pass\n")
    os.chmod(path, mode)
    with pytest.raises(InsecureSecretError, match=f"mode {mode:03o}.*chmod 600"):
        load_secret(path)


def test_a_fifo_as_the_secret_file_is_refused_without_hanging(
    tmp_path: os.PathLike[str],
) -> None:
    path = os.path.join(tmp_path, "secret")
    os.mkfifo(path, 0o600)
    with pytest.raises(InsecureSecretError, match="not a regular file"):
        load_secret(path)  # a plain open() would wait for a writer forever


@pytest.mark.parametrize("secret", ["x", "fifteen-bytes!!", b"\x00" * 15])
def test_a_secret_under_16_bytes_is_refused(secret: str | bytes) -> None:
    with pytest.raises(InsecureSecretError, match=r"too short.*ego secret"):
        coerce_secret(secret)


def test_ego_secret_writes_a_new_private_file_once(tmp_path: os.PathLike[str]) -> None:
    path = os.path.join(tmp_path, "made")
    made = write_secret(path)
    assert len(made) >= 40 and oct(os.stat(path).st_mode & 0o777) == "0o600"
    assert load_secret(path) == made.encode()
    with pytest.raises(FileExistsError):
        write_secret(path)
    assert new_secret() != new_secret()


def test_empty_secret_means_none() -> None:
    assert coerce_secret("") is None
    assert coerce_secret("abcdefghijklmnop") == b"abcdefghijklmnop"


@pytest.mark.parametrize(
    ("error", "attributes"),
    [
        (
            ConfigSyntaxError("camera.conf", 3, "width must be an integer"),
            {"path": "camera.conf", "line_number": 3},
        ),
        (VersionMismatchError("version 9", 9, 4, 7), {"peer_version": 9, "seq": 4, "session": 7}),
        (PortBusyError("port held", holder_pid=1234), {"holder_pid": 1234}),
    ],
)
def test_errors_cross_the_network_as_their_class_with_their_fields(
    error: Exception, attributes: dict[str, object]
) -> None:
    """Classes whose constructors take more than a message used to crash the client with
    TypeError; now each is rebuilt as itself, fields included."""
    payload = pack_error(type(error).__name__, str(error), error_fields(error))
    rebuilt = error_from_reply(payload, "tcp://robot:4242")
    assert type(rebuilt) is type(error)
    assert str(rebuilt) == f"tcp://robot:4242: {error}"
    for key, value in attributes.items():
        assert getattr(rebuilt, key) == value


def test_a_directory_as_the_secret_file_is_refused_by_its_path(
    tmp_path: os.PathLike[str],
) -> None:
    path = os.fspath(tmp_path)
    with pytest.raises(InsecureSecretError) as caught:
        load_secret(path)
    assert str(caught.value) == f"{path}: is a directory, not a secret file"  # not "... : 3"
