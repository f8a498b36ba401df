"""Every parser fed random and mutated input: a typed error or a value in range, never a hang.

Fuzzed here: the dsPIC reply parser (``Batch.decode``) and the batch parser of the
server (``parse_batch``), the ASCII line parsers (``identify``, ``line_payload``,
``parse_selector``, ``Link.ascii_command`` and the firmware probe over a scripted
transport), the remote wire (frames, the stream reader, the payloads, URLs), the camera
configuration file, and the emulator's dsPIC. Each property says which errors are
allowed (ego's typed errors, and the builtin a docstring promises); anything else fails,
and so does an example slower than the deadline (a hang). Runs are derandomized, so CI
replays the same examples.
"""

from __future__ import annotations

import math
import struct
from collections.abc import Callable
from datetime import timedelta

import pytest
from fakes import INSTANT_LINK, ScriptedTransport
from helpers import SUBNORMALS
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import ego
from ego.backends.remote.channel import error_from_reply
from ego.camera.config import CameraConfiguration, parse_configuration, size_range
from ego.camera.convert import ROTATIONS
from ego.camera.source import CONTROLS
from ego.errors import (
    CameraConfigError,
    ConfigSyntaxError,
    EgoError,
    ExtraBytesError,
    FrameError,
    ProtocolError,
    SettingOutOfRangeError,
    ShortReplyError,
    UnknownSettingError,
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
from ego.seam.batch import Batch, Request
from ego.seam.profile import Command, Firmware, Profile
from ego.serial.firmware import identify, line_payload, parse_selector
from ego.serial.link import RESYNC, Link
from ego.serial.profiles import GCTRONIC_BLUETOOTH, PROFILES
from ego.serial.protocol import encode_batch, parse_batch
from firmware_sim import Dspic, World

#: Every fuzz test: the same examples on every run, a bounded count, and a deadline per
#: example that a hang (or a quadratic blow-up) cannot meet.
FUZZ = settings(
    derandomize=True,
    max_examples=150,
    deadline=timedelta(seconds=1),
    suppress_health_check=[HealthCheck.too_slow],
)
#: For properties whose examples wait on timeouts (the scripted transport sleeps them).
FUZZ_SLOW = settings(FUZZ, max_examples=40)

THESIS = PROFILES[Firmware.WEBOTS]
OVERO = PROFILES[Firmware.GCTRONIC]
PROFILE_LIST = [THESIS, OVERO]

#: The range of each struct code a reply may hold.
RANGES = {"h": (-(2**15), 2**15 - 1), "H": (0, 2**16 - 1), "B": (0, 255)}


def mutated(data: bytes, ops: list[tuple[int, int, int]]) -> bytes:
    """``data`` after each ``(kind, position, byte)``: flip, insert, delete or truncate."""
    out = bytearray(data)
    for kind, position, value in ops:
        at = position % (len(out) + 1)
        if kind == 0 and out:
            out[at % len(out)] ^= 1 << (value % 8)
        elif kind == 1:
            out.insert(at, value)
        elif kind == 2 and out:
            del out[at % len(out)]
        elif kind == 3:
            del out[at:]
    return bytes(out)


MUTATIONS = st.lists(
    st.tuples(st.integers(0, 3), st.integers(0, 1 << 16), st.integers(0, 255)),
    min_size=1,
    max_size=6,
)

# -- the dsPIC's replies and batches ---------------------------------------------------------


def requests_for(profile: Profile) -> st.SearchStrategy[Request]:
    """Any request the profile serves, with random arguments of the right width."""
    i16 = st.integers(-(2**15), 2**15 - 1)
    u8 = st.integers(0, 255)
    args = {
        Command.SET_SPEED: st.tuples(i16, i16),
        Command.SET_STEPS: st.tuples(i16, i16),
        Command.SET_LED: st.tuples(u8, u8),
    }
    commands = sorted(c for c in profile.commands if c is not Command.END)
    return st.sampled_from(commands).flatmap(
        lambda c: args.get(c, st.just(())).map(lambda a: Request(c, a))
    )


def check_values_in_range(batch: Batch, values: list[tuple[float, ...]]) -> None:
    """Each request's values: the count its formats give, each within its struct type."""
    assert len(values) == len(batch.requests)
    for fmt, got in zip(batch._formats, values, strict=True):
        codes = "".join(
            code * int(count or 1)
            for part in (fmt.prefix, fmt.reply)
            for count, code in _struct_codes(part.format)
        )
        assert len(got) == len(codes)
        for code, value in zip(codes, got, strict=True):
            if code == "f":
                assert isinstance(value, float)
                assert math.isnan(value) or abs(value) <= 3.5e38
            else:
                low, high = RANGES[code]
                assert isinstance(value, int) and low <= value <= high


def _struct_codes(fmt: str) -> list[tuple[str, str]]:
    import re

    return re.findall(r"(\d*)([a-zA-Z])", fmt.lstrip("<"))


@pytest.mark.parametrize("profile", PROFILE_LIST, ids=lambda p: str(p.firmware))
@FUZZ
@given(data=st.data())
def test_any_reply_decodes_to_values_in_range_or_a_length_error(
    profile: Profile, data: st.DataObject
) -> None:
    requests = data.draw(st.lists(requests_for(profile), min_size=1, max_size=8))
    batch = encode_batch(requests, profile)
    size = data.draw(
        st.one_of(st.just(batch.reply_size), st.integers(0, batch.reply_size + 8)), label="size"
    )
    reply = data.draw(st.binary(min_size=size, max_size=size), label="reply")
    try:
        values = batch.decode(reply)
    except ShortReplyError as exc:
        assert len(reply) < batch.reply_size and str(batch.reply_size) in str(exc)
    except ExtraBytesError as exc:
        assert len(reply) > batch.reply_size and str(batch.reply_size) in str(exc)
    else:
        assert len(reply) == batch.reply_size, "a reply of the wrong length was decoded"
        check_values_in_range(batch, values)


#: Bytes that mean something to the batch parser, beside any byte at all.
COMMAND_BYTES = [int(c) for c in Command]


@pytest.mark.parametrize("profile", PROFILE_LIST, ids=lambda p: str(p.firmware))
@FUZZ
@given(
    raw=st.lists(st.one_of(st.sampled_from(COMMAND_BYTES), st.integers(0, 255)), max_size=40).map(
        bytes
    )
)
def test_the_server_batch_parser_gives_a_batch_of_these_bytes_or_value_error(
    profile: Profile, raw: bytes
) -> None:
    try:
        batch = parse_batch(raw, profile)
    except ValueError as exc:  # parse_batch's documented refusal
        assert type(exc) is ValueError, f"{type(exc).__name__} leaked: {exc}"
        return
    assert batch.tx == raw and batch.requests
    assert batch.reply_size == sum(
        profile.wire_format(r.command).prefix.size + profile.wire_format(r.command).reply.size
        for r in batch.requests
    )


@pytest.mark.parametrize("profile", PROFILE_LIST, ids=lambda p: str(p.firmware))
@FUZZ
@given(data=st.data(), ops=MUTATIONS)
def test_a_mutated_batch_parses_to_itself_or_is_refused(
    profile: Profile, data: st.DataObject, ops: list[tuple[int, int, int]]
) -> None:
    requests = data.draw(st.lists(requests_for(profile), min_size=1, max_size=8))
    raw = mutated(encode_batch(requests, profile).tx, ops)
    try:
        batch = parse_batch(raw, profile)
    except ValueError as exc:
        assert type(exc) is ValueError, f"{type(exc).__name__} leaked: {exc}"
        return
    assert batch.tx == raw
    assert parse_batch(batch.tx, profile) == batch


# -- the ASCII lines ------------------------------------------------------------------------

#: Lines a firmware, a wrong device or line noise may send.
LINES = st.one_of(
    st.text(max_size=60),
    st.sampled_from(
        [
            "v,Version 1.2.2 August 2008 GCtronic",
            "v,Version 1.5.3 November 2016 (Webots)",
            "HW version: 1.3",
            "c,10",
            "c,3",
            "c,16",
            "c,-1",
            "c,1\u0660",
            "v,",
            "v",
            "",
        ]
    ),
)


@FUZZ
@given(lines=st.lists(LINES, max_size=3), selector=st.one_of(st.none(), st.integers(-5, 20)))
def test_identify_gives_a_known_profile_or_a_protocol_error(
    lines: list[str], selector: int | None
) -> None:
    try:
        info = identify(lines, selector)
    except ProtocolError:
        assert lines and not lines[0].strip().startswith("v,")
        return
    assert info.firmware in (Firmware.WEBOTS, Firmware.GCTRONIC)
    known = [*PROFILES.values(), GCTRONIC_BLUETOOTH]
    assert any(info.profile.commands.items() <= p.commands.items() for p in known)


@FUZZ
@given(line=LINES, letter=st.sampled_from(["V", "C", "S", "K"]))
def test_line_payload_and_selector_give_text_and_0_to_15_or_a_protocol_error(
    line: str, letter: str
) -> None:
    try:
        payload = line_payload(line, letter)
    except ProtocolError:
        assert not line.strip().startswith(letter.lower() + ",")
    else:
        assert line.strip() == f"{letter.lower()},{payload}"
    try:
        selector = parse_selector(line)
    except ProtocolError:
        return
    assert isinstance(selector, int) and 0 <= selector <= 15


#: Raw bytes a port may answer an ASCII command with: lines, noise, no end of line.
ANSWERS = st.one_of(
    st.binary(max_size=80),
    st.lists(LINES, max_size=3).map(lambda ls: "".join(s + "\r\n" for s in ls).encode()),
)


@FUZZ_SLOW
@given(answer=ANSWERS, letter=st.sampled_from(["V", "C", "S", "K"]), lines=st.integers(1, 2))
def test_an_ascii_command_gives_its_reply_lines_or_a_protocol_error(
    answer: bytes, letter: str, lines: int
) -> None:
    transport = ScriptedTransport()
    link = Link(transport, Firmware.WEBOTS, INSTANT_LINK)  # told the firmware: no probe
    transport.script.append(answer)
    try:
        replies = link.ascii_command(letter, lines)
    except ProtocolError as exc:
        assert letter.lower() in str(exc)
        return
    assert len(replies) <= lines
    assert all(r and r == r.strip() and "\n" not in r for r in replies)
    if replies:
        assert replies[0].startswith(letter.lower())


@FUZZ_SLOW
@given(version=ANSWERS, selector=ANSWERS)
def test_the_firmware_probe_ends_in_a_profile_or_a_typed_error(
    version: bytes, selector: bytes
) -> None:
    """Whatever a port answers to ``V`` and ``C``, opening a link ends, typed."""
    try:
        link = Link(ScriptedTransport([version, selector]), settings=INSTANT_LINK)
    except EgoError:
        return
    assert link.profile.firmware in (Firmware.WEBOTS, Firmware.GCTRONIC)
    assert link.info.selector is None or 0 <= link.info.selector <= 15


# -- the remote wire ------------------------------------------------------------------------

U32 = st.integers(0, 2**32 - 1)
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


# -- the camera configuration file -------------------------------------------------------------

VALID_FILE = """# e-puck camera, as E-GO starts it
width = 640                # pixels
height = 480
rotation = 180
fov_rad = 0.84
brightness = 1
contrast = 64
saturation = 64
auto_white_balance = off
"""


def check_configuration(text: str) -> None:
    """A configuration in range, or a located CameraConfigError of one of its three kinds."""
    try:
        config = parse_configuration(text, "fuzz.conf")
    except CameraConfigError as exc:
        assert type(exc) in (ConfigSyntaxError, UnknownSettingError, SettingOutOfRangeError)
        assert 1 <= exc.line_number <= max(1, len(text.splitlines()))  # type: ignore[attr-defined]
        assert str(exc).startswith(f"fuzz.conf:{exc.line_number}: ")  # type: ignore[attr-defined]
        return
    assert isinstance(config, CameraConfiguration)
    rotation = 180 if config.rotation is None else config.rotation
    assert rotation in ROTATIONS
    low, high = size_range(rotation)
    if config.width is not None:
        assert type(config.width) is int and low[0] <= config.width <= high[0]
    if config.height is not None:
        assert type(config.height) is int and low[1] <= config.height <= high[1]
    if config.fov_rad is not None:
        assert 0.0 < config.fov_rad < math.pi
    for name, value in config.controls().items():
        assert CONTROLS[name].minimum <= value <= CONTROLS[name].maximum
    assert config.auto_white_balance in (None, True, False)


@FUZZ
@given(text=st.text(max_size=200))
def test_any_text_is_a_configuration_in_range_or_a_located_error(text: str) -> None:
    check_configuration(text)


#: A value for each key around the edges of its range, or junk.
VALUES = {
    "width": st.integers(0, 700),
    "height": st.integers(0, 700),
    "rotation": st.sampled_from([0, 45, 90, 180, 270, 360, -90]),
    "fov_rad": st.one_of(
        st.floats(-0.5, 4.5, allow_subnormal=SUBNORMALS),
        st.sampled_from([0.0, 1e-9, 3.1415, 3.1416, 3.5, 4.0]),
    ),
    "brightness": st.integers(-10, 300),
    "contrast": st.integers(-10, 300),
    "saturation": st.integers(-10, 300),
    "auto_white_balance": st.sampled_from(["on", "off", "yes", "no", "1", "0", "2", "maybe"]),
    "zoom": st.integers(0, 9),
}
#: Lines of ``key = value``, every key (and one unknown) with a value near its edges; junk
#: values are the other tests' business.
SETTING_LINES = st.lists(
    st.sampled_from(sorted(VALUES)).flatmap(
        lambda key: VALUES[key].map(lambda value: f"{key} = {value}")
    ),
    max_size=3,
).map("\n".join)


@FUZZ
@given(text=SETTING_LINES)
def test_any_settings_are_a_configuration_in_range_or_a_located_error(text: str) -> None:
    check_configuration(text)


#: Text edits of a valid file: at a position, insert, delete or replace some text.
EDITS = st.lists(
    st.tuples(
        st.integers(0, 3),
        st.integers(0, len(VALID_FILE)),
        st.one_of(
            st.text(max_size=6),
            st.sampled_from(
                ["=", "#", "\n", "-", "9", "0", "_", "e5", "nan", "\uff10", "width = 32\n"]
            ),
        ),
    ),
    min_size=1,
    max_size=5,
)


@FUZZ
@given(edits=EDITS)
def test_a_mutated_valid_file_is_a_configuration_in_range_or_a_located_error(
    edits: list[tuple[int, int, str]],
) -> None:
    text = VALID_FILE
    for kind, position, piece in edits:
        at = position % (len(text) + 1)
        if kind == 0:
            text = text[:at] + piece + text[at:]
        elif kind == 1:
            text = text[:at] + text[at + len(piece) + 1 :]
        elif kind == 2:
            text = text[:at] + piece + text[at + len(piece) :]
        else:  # a line said twice
            lines = text.splitlines(keepends=True)
            if lines:
                line = lines[at % len(lines)]
                text = text + line
    check_configuration(text)


# -- the emulator's dsPIC ---------------------------------------------------------------------

#: Bytes that steer the dsPIC's parser: command bytes, the batch end, line ends, letters.
DSPIC_BYTES = st.lists(
    st.one_of(
        st.sampled_from([*COMMAND_BYTES, 0x9D, 0x0A, 0x0D, *b"VSCKRvz"]),
        st.integers(0, 255),
    ),
    max_size=200,
).map(bytes)
E_BATCH = encode_batch([Request(Command.GET_SPEED)], THESIS).tx


@pytest.mark.parametrize("firmware", ["webots", "gctronic"])
@FUZZ
@given(garbage=DSPIC_BYTES)
def test_the_dspic_survives_any_bytes_and_the_resync_brings_it_back(
    firmware: str, garbage: bytes
) -> None:
    """Random bytes never raise in the emulator, leave its world in range, and the link's
    resynchronisation always returns it to a state where the next batch is answered."""
    world = World(seed=1)
    dspic = Dspic(world, firmware)
    for emission in dspic.feed(garbage):
        assert isinstance(emission.data, bytes)
        assert emission.kind in ("reply", "prefix", "ascii", "banner")
    left, right = world.speeds
    assert -1000 <= left <= 1000 and -1000 <= right <= 1000
    assert all(led in (0, 1) for led in world.leds)

    dspic.feed(RESYNC)
    replies = [e for e in dspic.feed(E_BATCH) if e.kind == "reply"]
    assert len(replies) == 1
    # E echoes what D asked, unclamped (Asercom.c 'E'); the wheels run clamped.
    echo = struct.unpack("<2h", replies[0].data)
    assert echo == dspic.echo
    assert world.speeds == tuple(max(-1000, min(1000, v)) for v in echo)


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
