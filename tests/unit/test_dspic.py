"""The emulated dsPIC (firmware_sim.dspic) on bytes alone, for both firmware profiles.

These tests pin the emulator to protocol.md, so that the library's own tests against the
emulator prove something about the real robot.
"""

from __future__ import annotations

import struct
from typing import Any

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ego.seam.batch import Request
from ego.seam.profile import Firmware
from ego.serial.profiles import BANNER_MARKER, PROFILES
from ego.serial.protocol import encode_batch
from firmware_sim import BANNER, Dspic, World
from firmware_sim.dspic import FIRMWARES, Emission


def neg(letter: str) -> int:
    return (-ord(letter)) & 0xFF


def batch(*letters: str, args: bytes = b"") -> bytes:
    """Command bytes of ``letters`` then 0x00 (``args`` follow the first command)."""
    head, *rest = letters
    return bytes([neg(head)]) + args + bytes(neg(c) for c in rest) + b"\x00"


def make(firmware: str = "webots", **variant: Any) -> Dspic:
    return Dspic(World(seed=3, noise=False), firmware, **variant)


def replies(emissions: list[Emission]) -> list[Emission]:
    return [e for e in emissions if e.kind == "reply"]


def only_reply(emissions: list[Emission]) -> bytes:
    (reply,) = replies(emissions)
    return reply.data


def text(emissions: list[Emission]) -> list[str]:
    (line,) = emissions
    assert line.kind == "ascii"
    return line.data.decode("ascii").split("\r\n")[:-1]


# -- binary batches ----------------------------------------------------------------------------


def test_full_sensor_step_answers_58_bytes_on_thesis() -> None:
    dspic = make()
    out = dspic.feed(bytes.fromhex("9f bb b3 b2 b1 af 8b 00"))
    data = only_reply(out)
    assert len(data) == 58
    record = out[-1].record
    assert record is not None
    assert record.commands == "aEMNOQu"
    assert record.reply == data
    assert record.index == dspic.batches == 1


def test_replies_are_the_worlds_values_little_endian_in_command_order() -> None:
    """protocol.md: "replies back to back, in command order, with no header, no length"."""
    dspic = make()
    world = dspic.world
    data = only_reply(dspic.feed(batch("N", "M", "O", "Q", "E")))
    expected = (
        struct.pack("<8h", *world.proximity())
        + struct.pack("<3H", *world.floor())
        + struct.pack("<8h", *world.light())
        + struct.pack("<2h", *world.steps_int16())
        + struct.pack("<2h", *world.speeds)
    )
    assert data == expected


def test_full_sensor_step_on_gctronic_overo_skips_floor_and_widens_n_and_o() -> None:
    """protocol.md: "N and O return 10 values (20 bytes)", "M returns nothing"."""
    dspic = make("gctronic")
    out = dspic.feed(bytes.fromhex("9f bb b3 b2 b1 af 8b 00"))
    assert len(only_reply(out)) == 6 + 4 + 0 + 20 + 20 + 4 + 6
    assert out[-1].record is not None
    assert out[-1].record.commands == "aEMNOQu"


@pytest.mark.parametrize(("firmware", "size"), [("webots", 16), ("gctronic", 20)])
@pytest.mark.parametrize("letter", ["N", "O"])
def test_proximity_and_light_sizes_follow_the_firmware(
    firmware: str, size: int, letter: str
) -> None:
    assert len(only_reply(make(firmware).feed(batch(letter)))) == size


def test_overo_long_range_sensors_follow_ps0_to_ps7() -> None:
    dspic = make("gctronic")
    values = struct.unpack("<10h", only_reply(dspic.feed(batch("N"))))
    assert list(values) == dspic.world.proximity(long_range=True)


def test_floor_sensors_are_silent_on_gctronic_overo() -> None:
    dspic = make("gctronic")
    assert only_reply(dspic.feed(batch("M"))) == b""
    assert only_reply(dspic.feed(batch("E", "M", "Q"))) == bytes(8)


@pytest.mark.parametrize(
    ("letter", "size"), [("a", 6), ("A", 12), ("E", 4), ("M", 6), ("Q", 4), ("u", 6), ("b", 0)]
)
def test_each_sensor_reply_has_its_table_size_on_webots(letter: str, size: int) -> None:
    """firmware.c: each case's buffer[i++] count; no case 'b' (skipped: nothing sent)."""
    assert len(only_reply(make().feed(batch(letter)))) == size


@pytest.mark.parametrize("firmware", FIRMWARES)
def test_emulator_and_library_agree_on_every_reply_size(firmware: str) -> None:
    """Two independent readings of protocol.md (the emulator's and ego's) must agree."""
    profile = PROFILES[Firmware(firmware)]
    for command, wire in profile.commands.items():
        encoded = encode_batch([Request(command, (0, 0) if wire.arguments.size else ())], profile)
        out = make(firmware).feed(encoded.tx)
        sent = sum(len(e.data) for e in out if e.kind in ("reply", "prefix"))
        assert sent == encoded.reply_size, command.letter


def test_microphone_buffer_goes_out_first_when_u_is_parsed() -> None:
    """protocol.md: U's 600 bytes are "sent at once when parsed", they "arrive before the
    rest of the batch's replies", and "the 1 batched byte is the index of the newest sample"."""
    dspic = make()
    out = dspic.feed(batch("E", "U", "Q"))
    assert [e.kind for e in out] == ["prefix", "reply"]
    prefix, reply = out
    assert len(prefix.data) == 600
    assert len(reply.data) == 4 + 1 + 4
    assert 0 <= reply.data[4] < 100
    assert reply.record is not None
    assert reply.record.reply == prefix.data + reply.data


def test_microphone_buffer_is_emitted_before_the_batch_ends() -> None:
    dspic = make()
    out = dspic.feed(bytes([neg("U")]))
    assert [e.kind for e in out] == ["prefix"]
    assert [e.kind for e in dspic.feed(b"\x00")] == ["reply"]


def test_actuator_only_batch_answers_nothing() -> None:
    """protocol.md: "A batch that asks for nothing (only D, L, P) gets no reply at all"."""
    dspic = make()
    out = dspic.feed(bytes.fromhex("b0 0a 00 f6 ff b4 01 01 bc 2c 01 d4 fe 00"))
    assert only_reply(out) == b""
    assert dspic.world.leds[1] == 1
    assert dspic.world.speeds == (300, -300)
    left, right = dspic.world.steps_int16()  # set to 10, -10, then the wheels turned
    assert left >= 10
    assert right <= -10


def test_speeds_are_clamped_to_1000_but_e_echoes_what_was_asked() -> None:
    """e_motors.c clamps to +-1000; Asercom.c 'E' sends speedl/speedr as D set them."""
    dspic = make()
    data = only_reply(dspic.feed(batch("D", "E", args=struct.pack("<2h", 1500, -32768))))
    assert struct.unpack("<2h", data) == (1500, -32768)
    assert dspic.world.speeds == (1000, -1000)


def test_unknown_command_bytes_are_skipped() -> None:
    """protocol.md: "Unknown command bytes are skipped silently by the firmware"."""
    dspic = make()
    out = dspic.feed(bytes.fromhex("bb 80 c5 41 01 af 00"))
    assert len(only_reply(out)) == 8
    assert out[-1].record is not None
    assert out[-1].record.commands == "EQ"


def test_gyro_answers_six_zeros_only_on_gctronic_overo() -> None:
    """protocol.md: "g returns 6 zero bytes" on the stock Overo firmware."""
    assert only_reply(make("gctronic").feed(batch("g"))) == bytes(6)
    assert only_reply(make("webots").feed(batch("g"))) == b""


def test_lone_zeros_are_ignored() -> None:
    """protocol.md: "A lone 0x00 outside a batch is ignored"."""
    dspic = make()
    assert dspic.feed(bytes(8)) == []
    assert dspic.batches == 0


def test_zeros_complete_pending_arguments_then_end_the_batch() -> None:
    """protocol.md: "a dsPIC waiting for D/L/P arguments takes them as speed 0 ... harmless"."""
    dspic = make()
    dspic.feed(batch("D", args=struct.pack("<2h", 500, 500)))
    out = dspic.feed(bytes([neg("D"), 0x2C]) + bytes(8))
    assert only_reply(out) == b""
    assert dspic.world.speeds == (0x2C, 0)
    assert dspic.batches == 2


@pytest.mark.parametrize("led", [8, 9])
def test_body_and_front_leds_are_ignored_on_gctronic_overo(led: int) -> None:
    """protocol.md: "L 8 and L 9 (body, front) are ignored"."""
    overo, thesis = make("gctronic"), make()
    overo.feed(batch("L", args=bytes([led, 1])))
    thesis.feed(batch("L", args=bytes([led, 1])))
    assert overo.world.leds[led] == 0
    assert thesis.world.leds[led] == 1


def test_led_value_two_toggles_and_other_numbers_set_the_whole_ring() -> None:
    """protocol.md: "value 0 off, 1 on, 2 toggle; any other led number sets all 8 ring LEDs"."""
    dspic = make()
    dspic.feed(batch("L", args=bytes([3, 2])))
    assert dspic.world.leds[3] == 1
    dspic.feed(batch("L", args=bytes([3, 2])))
    assert dspic.world.leds[3] == 0
    dspic.feed(batch("L", args=bytes([42, 1])))
    assert dspic.world.leds == (1,) * 8 + (0, 0)


def test_hardware_1_3_on_gctronic_overo_reads_zeros_from_the_accelerometer() -> None:
    """Asercom.c 'a'/'A' with use_bt == 0: `if(isEpuckVersion1_3())` zeros (ego refuses them)."""
    dspic = make("gctronic", rev13=True)
    assert only_reply(dspic.feed(batch("a", "A"))) == bytes(18)
    assert only_reply(make("gctronic").feed(batch("a"))) != bytes(6)


def test_accelerometer_at_rest_sees_one_g_on_z() -> None:
    """protocol.md: "0 g near 2000-2048, about 800 counts per g"."""
    x, y, z = struct.unpack("<3H", only_reply(make().feed(batch("a"))))
    assert 1950 <= x <= 2100
    assert 1950 <= y <= 2100
    assert 2750 <= z <= 2850


def test_step_counters_wrap_at_16_bits() -> None:
    """protocol.md: "they wrap at +-32768"."""
    dspic = make()
    dspic.feed(batch("P", args=struct.pack("<2h", 32767, -32768)))
    assert dspic.world.steps_int16() == (32767, -32768)


@settings(max_examples=30, deadline=None)
@given(cuts=st.lists(st.integers(1, 30), max_size=6))
def test_bytes_split_anywhere_give_the_same_replies(cuts: list[int]) -> None:
    """The serial line delivers bytes in arbitrary chunks; the parser must not care."""
    stream = (
        batch("P", "N", "E", "Q", args=struct.pack("<2h", 100, -100))  # the robot stays put
        + bytes(3)
        + batch("O", "Q", "M")
        + b"V\n"
        + batch("L", "a", args=b"\x02\x01")
    )
    whole = make().feed(stream)
    dspic = make()
    pieces, pos = [], 0
    for cut in sorted(set(cuts)):
        pieces.append(stream[pos:cut])
        pos = cut
    pieces.append(stream[pos:])
    split = [e for piece in pieces for e in dspic.feed(piece)]
    assert [(e.kind, e.data) for e in split] == [(e.kind, e.data) for e in whole]


# -- ASCII commands ----------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("firmware", "version"),
    [
        ("webots", "v,Version 1.5.3 November 2016 (Webots)"),
        ("gctronic", "v,Version 1.2.2 August 2008 GCtronic"),
    ],
)
def test_v_names_the_firmware_in_two_lines(firmware: str, version: str) -> None:
    """Asercom.c 'V': the version line, then sprintf("HW version: %X", HWversion)."""
    assert text(make(firmware, hardware_version=0x1300).feed(b"V\n")) == [
        version,
        "HW version: 1300",
    ]
    assert text(make(firmware).feed(b"V\n"))[1] == "HW version: FFFF"  # never written


@pytest.mark.parametrize(("firmware", "selector"), [("webots", "c,3"), ("gctronic", "c,10")])
def test_c_answers_the_selector(firmware: str, selector: str) -> None:
    """protocol.md: "C (selector; reply c,N)", 10 being the Overo mode."""
    assert text(make(firmware).feed(b"C\n")) == [selector]


def test_s_stops_the_motors_and_turns_the_leds_off() -> None:
    """protocol.md: "S (stop motors, LEDs off; reply s)"."""
    dspic = make()
    dspic.feed(batch("D", args=struct.pack("<2h", 400, 400)))
    dspic.feed(batch("L", args=bytes([8, 1])))
    assert dspic.world.speeds == (400, 400)
    assert dspic.world.leds[8] == 1
    assert text(dspic.feed(b"S\n")) == ["s"]
    assert dspic.world.speeds == (0, 0)
    assert dspic.world.leds == (0,) * 10


@pytest.mark.parametrize(("firmware", "seconds"), [("gctronic", 1.0), ("webots", 1.5)])
def test_k_answers_a_line_then_calibrates_deaf_then_its_last_line(
    firmware: str, seconds: float
) -> None:
    """Asercom.c / firmware.c 'K': "k, Starting calibration - Remove any object in sensors
    range", busy loops and the calibration (the line unread), "k, Calibration finished"."""
    first, last = make(firmware).feed(b"K\n")
    assert first.data == b"k, Starting calibration - Remove any object in sensors range\r\n"
    assert (first.after_s, first.deaf_s) == (0.0, 0.0)
    assert last.data == b"k, Calibration finished\r\n"
    assert last.after_s == last.deaf_s == seconds


def test_r_resets_and_prints_the_banner() -> None:
    """protocol.md: "After reset the robot prints a welcome banner"."""
    dspic = make()
    dspic.feed(batch("D", args=struct.pack("<2h", 200, 200)))
    out = dspic.feed(b"R\n")
    # Asercom.c 'R': uart_send_static_text("r\r\n") then RESET(), whose banner follows.
    assert [(e.kind, e.data) for e in out] == [("banner", b"r\r\n" + BANNER)]
    assert dspic.world.speeds == (0, 0)


def test_banner_carries_the_marker_ego_watches_for() -> None:
    assert BANNER_MARKER in BANNER


def test_lower_case_ascii_commands_are_accepted() -> None:
    assert text(make().feed(b"c\n")) == ["c,3"]


def test_unknown_ascii_command_is_answered_not_ignored() -> None:
    (line,) = text(make().feed(b"?\n"))
    assert line.startswith("z,")


def test_an_ascii_line_is_answered_only_once_it_ends() -> None:
    dspic = make()
    assert dspic.feed(b"V") == []
    assert len(text(dspic.feed(b"\n"))) == 2


def test_zeros_do_not_end_an_ascii_line_but_a_newline_does() -> None:
    """protocol.md: "A positive first byte starts an ASCII line command ending in \\n". A
    stray positive byte outside a batch therefore swallows what follows until a newline,
    zeros included: the link's resynchronisation must send one."""
    dspic = make()
    assert dspic.feed(b"\x03" + batch("E") + bytes(8)) == []
    assert dspic.batches == 0
    out = dspic.feed(b"\nV\n")
    assert [e.kind for e in out] == ["ascii", "ascii"]
    assert len(only_reply(dspic.feed(batch("E")))) == 4


def test_unknown_firmware_is_refused() -> None:
    with pytest.raises(ValueError, match="firmware 'e-puck2'"):
        Dspic(World(), "e-puck2")
