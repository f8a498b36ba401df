"""The dsPIC protocol on bytes alone: golden bytes for both firmwares, decoding, round trips.

Every expectation here is written from protocol.md (quoted), not from ego's tables, so
that a slip in ``ego.serial.protocol`` shows up as a failure instead of being mirrored.
"""

from __future__ import annotations

import struct

import pytest
from helpers import SUBNORMALS
from hypothesis import given
from hypothesis import strategies as st

from ego.errors import ExtraBytesError, ShortReplyError, UnsupportedDeviceError
from ego.seam.batch import Request
from ego.seam.profile import Command, Firmware, Profile
from ego.serial.profiles import GCTRONIC_BLUETOOTH, PROFILES, command_byte, wire_time_s
from ego.serial.protocol import encode_batch, parse_batch, reply_sizes

THESIS = PROFILES[Firmware.WEBOTS]
OVERO = PROFILES[Firmware.GCTRONIC]
BLUETOOTH = GCTRONIC_BLUETOOTH


def req(letter: str, *args: int) -> Request:
    return Request(Command(command_byte(letter)), tuple(args))


def hexbytes(text: str) -> bytes:
    return bytes.fromhex(text)


# docs/protocol.md, Table 4.1: (letter, arguments, tx bytes of the one-command batch,
# reply bytes on `webots`, reply bytes on `gctronic` in Overo mode; None where refused).
GOLDEN = [
    ("a", (), "9f 00", 6, 6),
    ("A", (), "bf 00", 12, 12),
    ("D", (300, -300), "bc 2c 01 d4 fe 00", 0, 0),
    ("E", (), "bb 00", 4, 4),
    ("L", (3, 1), "b4 03 01 00", 0, 0),
    ("M", (), "b3 00", 6, None),
    ("N", (), "b2 00", 16, 20),
    ("O", (), "b1 00", 16, 20),
    ("P", (-1, 32767), "b0 ff ff ff 7f 00", 0, 0),
    ("Q", (), "af 00", 4, 4),
    ("u", (), "8b 00", 6, 6),
    ("U", (), "ab 00", 601, 601),
    ("b", (), "9e 00", None, 2),  # firmware.c has no case 'b'; Asercom.c answers 2 bytes
]

# protocol.md, Table 4.1: each reply's layout, little-endian ("All multi-byte values are
# little-endian. Signed where the table says i16"). U: "600 sent at once ... + 1 in the batch".
REPLY_FORMATS = {
    "a": "<3H",
    "A": "<3f",
    "E": "<2h",
    "M": "<3H",
    "N": "<8h",
    "O": "<8h",
    "Q": "<2h",
    "u": "<3H",
    "U": "<B",
}
# Asercom.c, use_bt == 0: N and O send 10 values (20 bytes), M sends nothing; 'b' 2 bytes.
OVERO_REPLY_FORMATS = {**REPLY_FORMATS, "N": "<10h", "O": "<10h", "b": "<H"}
del OVERO_REPLY_FORMATS["M"]
# Asercom.c, use_bt == 1 with CLIFF_SENSORS: M sends 6 ground bytes then 4 cliff bytes.
BLUETOOTH_REPLY_FORMATS = {**REPLY_FORMATS, "M": "<5H", "b": "<H"}
U_PREFIX = "<300h"
ARGUMENT_FORMATS = {"D": "<2h", "L": "<2B", "P": "<2h"}


# -- command bytes -------------------------------------------------------------------------


@pytest.mark.parametrize(("letter", "byte"), [("a", 0x9F), ("D", 0xBC), ("U", 0xAB), ("u", 0x8B)])
def test_command_byte_is_the_negative_of_the_letter(letter: str, byte: int) -> None:
    """protocol.md: "the negative of an ASCII letter: (-ord(c)) & 0xFF (a is 0x9F, D is 0xBC)"."""
    assert command_byte(letter) == byte
    assert Command(byte).letter == letter


@pytest.mark.parametrize("bad", ["", "ab", "é"])
def test_command_byte_refuses_anything_but_one_ascii_letter(bad: str) -> None:
    with pytest.raises(ValueError, match="one ASCII letter"):
        command_byte(bad)


def test_end_of_batch_is_zero_and_has_no_letter() -> None:
    """protocol.md: "0 | 0x00 | end of batch"."""
    assert Command.END == 0
    assert Command.END.letter == ""


def test_every_command_of_table_4_1_has_its_byte() -> None:
    epuck2 = {Command.GYRO_RAW, *(c for c in Command if c.value >= Command.TOF_ENABLE)}
    epuck1 = {c.letter for c in Command if c is not Command.END and c not in epuck2}
    assert epuck1 == {letter for letter, *_ in GOLDEN}
    # The e-puck2's commands below 'A' are named by their byte (docs/protocol.md, "e-puck2").
    assert Command.ALL_SENSORS.letter == "-0x08" and Command.TOF_ENABLE.letter == "-0x11"


def test_wire_time_is_ten_bits_a_byte() -> None:
    """protocol.md: "Wire time is 10 bits a byte: 43.4 us/byte at 230400"."""
    assert wire_time_s(1) == pytest.approx(43.4e-6, rel=1e-3)
    assert wire_time_s(66) == pytest.approx(2.865e-3, rel=1e-3)
    assert wire_time_s(10, baud=115200) == pytest.approx(10 * 10 / 115200)


# -- golden bytes: encode ----------------------------------------------------------------------


@pytest.mark.parametrize(("letter", "args", "tx", "reply", "_"), GOLDEN)
def test_each_command_encodes_to_its_golden_bytes_on_webots(
    letter: str, args: tuple[int, ...], tx: str, reply: int | None, _: int | None
) -> None:
    if reply is None:
        with pytest.raises(UnsupportedDeviceError, match="webots"):
            encode_batch([req(letter, *args)], THESIS)
        return
    batch = encode_batch([req(letter, *args)], THESIS)
    assert batch.tx == hexbytes(tx)
    assert batch.reply_size == reply


@pytest.mark.parametrize(("letter", "args", "tx", "_", "reply"), GOLDEN)
def test_each_command_encodes_to_its_golden_bytes_on_gctronic_overo(
    letter: str, args: tuple[int, ...], tx: str, _: int, reply: int | None
) -> None:
    if reply is None:
        with pytest.raises(UnsupportedDeviceError, match="gctronic"):
            encode_batch([req(letter, *args)], OVERO)
        return
    batch = encode_batch([req(letter, *args)], OVERO)
    assert batch.tx == hexbytes(tx)
    assert batch.reply_size == reply


def test_full_sensor_step_is_golden_on_thesis() -> None:
    """The thesis' step `a E M N O Q u` + 0: 8 bytes out, 6+4+6+16+16+4+6 = 58 back."""
    batch = encode_batch([req(c) for c in "aEMNOQu"], THESIS)
    assert batch.tx == hexbytes("9f bb b3 b2 b1 af 8b 00")
    assert batch.reply_size == 58
    assert batch.expects_reply


def test_floor_sensors_are_refused_on_gctronic_overo() -> None:
    """protocol.md: on the stock Overo firmware "M returns nothing" and a device the firmware
    cannot serve "raises a clear error when enabled; it never reads zeros"."""
    with pytest.raises(UnsupportedDeviceError, match=r"'M'"):
        encode_batch([req(c) for c in "aEMNOQu"], OVERO)


def test_full_sensor_step_without_floor_is_golden_on_gctronic_overo() -> None:
    """N and O are 20 bytes there: 6+4+20+20+4+6 = 60."""
    batch = encode_batch([req(c) for c in "aENOQu"], OVERO)
    assert batch.tx == hexbytes("9f bb b2 b1 af 8b 00")
    assert batch.reply_size == 60


def test_actuator_only_batch_expects_no_reply() -> None:
    """protocol.md: "A batch that asks for nothing (only D, L, P) gets no reply at all:
    never wait for one"."""
    batch = encode_batch([req("D", 1000, -1000), req("L", 8, 2), req("P", 0, 0)], THESIS)
    assert batch.tx == hexbytes("bc e8 03 18 fc b4 08 02 b0 00 00 00 00 00")
    assert batch.reply_size == 0
    assert not batch.expects_reply
    assert batch.decode(b"") == [(), (), ()]


def test_reply_to_an_actuator_only_batch_is_extra_bytes() -> None:
    batch = encode_batch([req("D", 0, 0)], THESIS)
    with pytest.raises(ExtraBytesError):
        batch.decode(b"\x00")


def test_empty_batch_sends_nothing() -> None:
    batch = encode_batch([], THESIS)
    assert batch.tx == b""
    assert not batch.expects_reply


def test_argument_bytes_may_be_zero_inside_a_batch() -> None:
    """protocol.md: "Its argument bytes follow raw (they may be 0x00)"."""
    batch = encode_batch([req("D", 0, 0), req("E")], THESIS)
    assert batch.tx == hexbytes("bc 00 00 00 00 bb 00")
    assert batch.reply_size == 4


@pytest.mark.parametrize(
    ("request_", "message"),
    [
        (req("D", 1), "takes arguments"),
        (req("D", 1, 2, 3), "takes arguments"),
        (req("D", 40000, 0), "takes arguments"),
        (req("L", 256, 1), "takes arguments"),
        (req("L", -1, 1), "takes arguments"),
        (req("E", 5), "takes arguments"),
    ],
)
def test_arguments_that_do_not_fit_the_wire_are_refused(request_: Request, message: str) -> None:
    with pytest.raises(ValueError, match=message):
        encode_batch([request_], THESIS)


def test_reply_sizes_per_command_follow_each_profile() -> None:
    commands = [Command(command_byte(c)) for c in "aENOQuU"]
    assert reply_sizes(THESIS, commands) == [6, 4, 16, 16, 4, 6, 601]
    assert reply_sizes(OVERO, commands) == [6, 4, 20, 20, 4, 6, 601]


def test_profiles_drive_the_leds_each_firmware_serves() -> None:
    """protocol.md: "L 8 and L 9 (body, front) are ignored" on the stock Overo firmware."""
    assert THESIS.leds == tuple(range(10))
    assert OVERO.leds == tuple(range(8))


def test_profile_without_a_command_refuses_it_and_says_why() -> None:
    reduced = OVERO.without(Command.ACCELEROMETER_RAW, why="hardware 1.3")
    assert not reduced.supports(Command.ACCELEROMETER_RAW)
    assert reduced.supports(Command.PROXIMITY)
    assert reduced.supports(Command.END)
    with pytest.raises(UnsupportedDeviceError, match=r"hardware 1\.3"):
        encode_batch([req("a")], reduced)
    assert OVERO.supports(Command.ACCELEROMETER_RAW), "the shared profile must not change"


# -- golden bytes: decode ----------------------------------------------------------------------


def test_sensor_step_reply_decodes_per_command_on_thesis() -> None:
    """Replies come "back to back, in command order", little-endian; N/O/E/Q are i16."""
    batch = encode_batch([req(c) for c in "aEMNOQu"], THESIS)
    reply = hexbytes(
        "d0 07 00 08 ff ff"  # a: u16 2000, 2048, 65535 (unsigned)
        "18 fc e8 03"  # E: i16 -1000, 1000
        "e8 03 2c 01 00 00"  # M: u16 1000, 300, 0
        "fb ff 00 00 ff 0f 01 00 00 01 00 80 ff 7f 64 00"  # N: -5, 0, 4095, 1, 256, min, max, 100
        "a0 0f 00 00 90 01 ff 0f 00 00 00 00 00 00 0a 00"  # O: 4000, 0, 400, 4095, 0, 0, 0, 10
        "00 80 ff 7f"  # Q: i16 -32768, 32767
        "00 00 ff 0f 40 9c"  # u: u16 0, 4095, 40000
    )
    assert len(reply) == 58
    assert batch.decode(reply) == [
        (2000, 2048, 65535),
        (-1000, 1000),
        (1000, 300, 0),
        (-5, 0, 4095, 1, 256, -32768, 32767, 100),
        (4000, 0, 400, 4095, 0, 0, 0, 10),
        (-32768, 32767),
        (0, 4095, 40000),
    ]


def test_proximity_and_light_decode_ten_values_on_gctronic_overo() -> None:
    """protocol.md: "N and O return 10 values (20 bytes): ps0-ps7 plus ... IR8 left, IR9 right"."""
    batch = encode_batch([req("N"), req("O")], OVERO)
    prox = list(range(-2, 8))
    light = list(range(100, 1100, 100))
    reply = struct.pack("<10h", *prox) + struct.pack("<10h", *light)
    assert batch.decode(reply) == [tuple(prox), tuple(light)]


def test_spherical_acceleration_decodes_three_floats() -> None:
    """protocol.md: "A ... 12: 3 x f32: magnitude, orientation, inclination"."""
    batch = encode_batch([req("A")], THESIS)
    (values,) = batch.decode(hexbytes("00 00 80 3f 00 00 b4 42 00 00 34 42"))
    assert values == (1.0, 90.0, 45.0)


def test_battery_decodes_one_unsigned_word() -> None:
    """Asercom.c, 'b': the raw ADC count low byte first on a rev 1.3, else [BATT_LOW, 0]."""
    batch = encode_batch([req("b")], OVERO)
    assert batch.decode(hexbytes("c4 0b")) == [(3012,)]
    assert batch.decode(hexbytes("01 00")) == [(1,)]


def test_microphone_buffer_arrives_before_the_batch_replies() -> None:
    """protocol.md: U's "600 bytes arrive before the rest of the batch's replies", and "the 1
    batched byte is the index of the newest sample"."""
    batch = encode_batch([req("E"), req("U"), req("Q")], THESIS)
    samples = [(-1) ** i * i for i in range(300)]
    reply = (
        struct.pack("<300h", *samples) + hexbytes("0a 00 f6 ff") + b"\x63" + hexbytes("05 00 fb ff")
    )
    assert batch.reply_size == 600 + 4 + 1 + 4
    speeds, mic, steps = batch.decode(reply)
    assert speeds == (10, -10)
    assert mic == (*samples, 99)
    assert steps == (5, -5)


def test_two_microphone_buffers_both_come_first_in_command_order() -> None:
    batch = encode_batch([req("U"), req("b"), req("U")], OVERO)
    first, second = list(range(300)), list(range(-300, 0))
    reply = (
        struct.pack("<300h", *first)
        + struct.pack("<300h", *second)
        + b"\x01"
        + hexbytes("d8 0e")
        + b"\x02"
    )
    assert batch.decode(reply) == [(*first, 1), (3800,), (*second, 2)]


def test_short_reply_is_refused() -> None:
    """protocol.md: "treat a short read, or bytes left over after it, as a fault"."""
    batch = encode_batch([req("E")], THESIS)
    with pytest.raises(ShortReplyError, match="3 bytes"):
        batch.decode(b"\x00\x00\x00")


def test_overlong_reply_is_refused() -> None:
    batch = encode_batch([req("E")], THESIS)
    with pytest.raises(ExtraBytesError, match="5 bytes"):
        batch.decode(b"\x00" * 5)


def test_decode_accepts_a_memoryview() -> None:
    batch = encode_batch([req("Q")], THESIS)
    assert batch.decode(memoryview(bytearray(hexbytes("01 00 02 00")))) == [(1, 2)]


# -- parse_batch (a relay's view) --------------------------------------------------------------


def test_parse_batch_reads_back_the_full_sensor_step() -> None:
    batch = parse_batch(hexbytes("9f bb b3 b2 b1 af 8b 00"), THESIS)
    assert [r.command.letter for r in batch.requests] == list("aEMNOQu")
    assert batch.reply_size == 58


def test_parse_batch_reads_arguments_that_contain_zeros() -> None:
    batch = parse_batch(hexbytes("bc 00 00 00 00 b4 00 00 00"), THESIS)
    assert batch.requests == (req("D", 0, 0), req("L", 0, 0))
    assert batch.reply_size == 0


def test_parse_batch_sizes_n_by_profile() -> None:
    assert parse_batch(hexbytes("b2 00"), THESIS).reply_size == 16
    assert parse_batch(hexbytes("b2 00"), OVERO).reply_size == 20


@pytest.mark.parametrize(
    ("tx", "profile", "message"),
    [
        ("", THESIS, "does not end with 0x00"),
        ("9f bb", THESIS, "does not end with 0x00"),
        ("00", THESIS, "at least one command"),
        ("9f 01 00", THESIS, "0x01 at 1"),
        ("b3 00", OVERO, "0xb3 at 0"),
        ("bc 01 00", THESIS, "lacks its arguments"),
        ("9f 00 bb 00", THESIS, "2 bytes after the end"),
        ("9f 00 00", THESIS, "1 bytes after the end"),
    ],
)
def test_parse_batch_refuses_bytes_that_are_not_one_batch(
    tx: str, profile: Profile, message: str
) -> None:
    with pytest.raises(ValueError, match=message):
        parse_batch(hexbytes(tx), profile)


# -- properties --------------------------------------------------------------------------------

i16 = st.integers(-32768, 32767)
u8 = st.integers(0, 255)


def requests_for(formats: dict[str, str]) -> st.SearchStrategy[Request]:
    sensors = st.sampled_from(sorted(formats)).map(lambda c: req(c))
    return st.one_of(
        sensors,
        st.tuples(i16, i16).map(lambda a: req("D", *a)),
        st.tuples(u8, u8).map(lambda a: req("L", *a)),
        st.tuples(i16, i16).map(lambda a: req("P", *a)),
    )


PROFILE_FORMATS = [
    (THESIS, REPLY_FORMATS),
    (OVERO, OVERO_REPLY_FORMATS),
    (BLUETOOTH, BLUETOOTH_REPLY_FORMATS),
]
PROFILE_IDS = ["webots", "overo", "bluetooth"]


@pytest.mark.parametrize(("profile", "formats"), PROFILE_FORMATS, ids=PROFILE_IDS)
@given(data=st.data())
def test_encoded_batches_parse_back_to_the_same_requests(
    profile: Profile, formats: dict[str, str], data: st.DataObject
) -> None:
    requests = data.draw(st.lists(requests_for(formats), min_size=1, max_size=12))
    batch = encode_batch(requests, profile)
    assert batch.tx[-1] == 0
    again = parse_batch(batch.tx, profile)
    assert list(again.requests) == requests
    assert again.tx == batch.tx
    assert again.reply_size == batch.reply_size


def value_for(fmt: str) -> st.SearchStrategy[tuple[float, ...]]:
    count, code = int(fmt[1:-1] or 1), fmt[-1]
    element = {
        "h": i16,
        "H": st.integers(0, 65535),
        "B": u8,
        "f": st.floats(width=32, allow_nan=False, allow_subnormal=SUBNORMALS),
    }[code]
    return st.tuples(*[element] * count)


@pytest.mark.parametrize(("profile", "formats"), PROFILE_FORMATS, ids=PROFILE_IDS)
@given(data=st.data())
def test_packed_values_decode_back_to_themselves(
    profile: Profile, formats: dict[str, str], data: st.DataObject
) -> None:
    letters = data.draw(st.lists(st.sampled_from(sorted(formats)), min_size=1, max_size=8))
    batch = encode_batch([req(c) for c in letters], profile)
    prefix, body, expected = b"", b"", []
    for letter in letters:
        values = data.draw(value_for(formats[letter]))
        body += struct.pack(formats[letter], *values)
        if letter == "U":  # the 600 bytes go out first, ahead of every in-batch reply
            raw = data.draw(st.binary(min_size=600, max_size=600))
            prefix += raw
            values = struct.unpack(U_PREFIX, raw) + values
        expected.append(values)
    assert batch.decode(prefix + body) == expected


@pytest.mark.parametrize(("profile", "formats"), PROFILE_FORMATS, ids=PROFILE_IDS)
@given(data=st.data())
def test_reply_parser_fed_random_bytes_gives_values_or_a_length_error(
    profile: Profile, formats: dict[str, str], data: st.DataObject
) -> None:
    requests = data.draw(st.lists(requests_for(formats), min_size=1, max_size=6))
    batch = encode_batch(requests, profile)
    size = data.draw(st.one_of(st.just(batch.reply_size), st.integers(0, batch.reply_size + 8)))
    reply = data.draw(st.binary(min_size=size, max_size=size))
    try:
        values = batch.decode(reply)
    except ShortReplyError:
        assert len(reply) < batch.reply_size
    except ExtraBytesError:
        assert len(reply) > batch.reply_size
    else:
        assert len(reply) == batch.reply_size
        assert len(values) == len(requests)


@given(tx=st.binary(max_size=40))
def test_parse_batch_fed_random_bytes_gives_a_batch_or_value_error(tx: bytes) -> None:
    for profile in (THESIS, OVERO):
        try:
            batch = parse_batch(tx, profile)
        except ValueError:
            continue
        assert batch.tx == tx
