"""The serial side fed random and mutated input: a typed error or a value in range, never a hang.

Fuzzed here: the dsPIC reply parser (``Batch.decode``) and the batch parser of the
server (``parse_batch``), the ASCII line parsers (``identify``, ``line_payload``,
``parse_selector``, ``Link.ascii_command`` and the firmware probe over a scripted
transport), and the emulator's dsPIC. Each property says which errors are allowed
(ego's typed errors, and the builtin a docstring promises); anything else fails, and so
does an example slower than the deadline (a hang). The shared settings: ``fuzzing.py``.
"""

from __future__ import annotations

import math
import struct

import pytest
from fakes import INSTANT_LINK, ScriptedTransport
from fuzzing import COMMAND_BYTES, FUZZ, FUZZ_SLOW, MUTATIONS, PROFILE_LIST, THESIS, mutated
from hypothesis import given
from hypothesis import strategies as st

from ego.errors import (
    EgoError,
    ExtraBytesError,
    ProtocolError,
    ShortReplyError,
)
from ego.seam.batch import Batch, Request
from ego.seam.profile import Command, Firmware, Profile
from ego.serial.firmware import identify, line_payload, parse_selector
from ego.serial.link import RESYNC, Link
from ego.serial.profiles import GCTRONIC_BLUETOOTH, PROFILES
from ego.serial.protocol import encode_batch, parse_batch
from firmware_sim import Dspic, World

#: The range of each struct code a reply may hold.
RANGES = {"h": (-(2**15), 2**15 - 1), "H": (0, 2**16 - 1), "B": (0, 255)}


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
