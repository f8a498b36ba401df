"""The Pi-puck's codecs without a bus: the e-puck2's 20/47-byte messages and York's map,
golden bytes from docs/protocol.md ("The Pi-puck")."""

from __future__ import annotations

import struct
from functools import reduce
from operator import xor

import pytest
from hypothesis import given
from hypothesis import strategies as st

from ego.backends.pipuck import york
from ego.backends.pipuck.epuck2 import fold
from ego.backends.pipuck.packet import (
    ActuatorPacket,
    Settings,
    checksum,
    decode_sensors,
    encode_actuators,
)
from ego.errors import ChecksumError, OutOfRangeError, ShortReplyError
from ego.seam.batch import Request
from ego.seam.profile import Command


def test_actuator_message_is_twenty_bytes_little_endian_with_xor_last() -> None:
    # protocol.md: "bytes 0-1 left speed, int16 little-endian ... byte 19 the XOR of 0..18"
    packet = ActuatorPacket(speed_left=-200, speed_right=1100,
                            red_leds=(True, False, False, True),
                            rgb_leds=((100, 0, 0), (0, 0, 0), (0, 0, 0), (0, 0, 50)),
                            sound=2)  # fmt: skip
    message = encode_actuators(packet)
    assert message[:4] == bytes([0x38, 0xFF, 0x4C, 0x04])  # -200 and 1100, low byte first
    assert message[4] == 2 and message[5] == 0b1001
    assert message[6:9] == bytes([100, 0, 0]) and message[15:18] == bytes([0, 0, 50])
    assert message[18] == 0
    assert len(message) == 20 and message[19] == reduce(xor, message[:19], 0)


def test_the_stop_message_is_all_zero_and_its_checksum_zero() -> None:
    assert encode_actuators(ActuatorPacket()) == bytes(20)


@pytest.mark.parametrize("speed", [1101, -1101, 5000])
def test_a_speed_beyond_the_firmware_limit_is_refused(speed: int) -> None:
    with pytest.raises(OutOfRangeError, match="1100"):
        encode_actuators(ActuatorPacket(speed_left=speed))


def test_rgb_is_a_percentage_not_a_byte() -> None:
    # protocol.md: "LED2, 4, 6, 8 as R, G, B, each 0..100"
    with pytest.raises(OutOfRangeError, match=r"0\.\.100"):
        encode_actuators(ActuatorPacket(rgb_leds=((255, 0, 0),) * 4))


def _reply(proximity: tuple[int, ...] = (0,) * 8, steps: tuple[int, int] = (0, 0),
           flags: int = 10, mics: tuple[int, ...] = (0,) * 4) -> bytes:  # fmt: skip
    data = struct.pack("<8h8h4HBhhB", *proximity, *range(8), *mics, flags, *steps, 7)
    return data + bytes([checksum(data)])


def test_sensor_reply_decodes_words_low_byte_first() -> None:
    reply = decode_sensors(_reply(proximity=(0x0102, 3, 4, 5, 6, 7, 8, 4095), flags=0x1A))
    assert reply.proximity[0] == 0x0102 and reply.proximity[7] == 4095
    assert reply.ambient == tuple(range(8))
    assert reply.selector == 10 and reply.button is True
    assert reply.tv_remote == 7


def test_step_counters_are_int16_and_wrap() -> None:
    raw = _reply(steps=(-32768, 32767))
    assert raw[41:45] == bytes([0x00, 0x80, 0xFF, 0x7F])
    assert decode_sensors(raw).steps == (-32768, 32767)


def test_a_reply_with_a_wrong_checksum_is_refused() -> None:
    raw = bytearray(_reply())
    raw[3] ^= 0x40
    with pytest.raises(ChecksumError):
        decode_sensors(bytes(raw))


def test_a_short_reply_is_refused() -> None:
    with pytest.raises(ShortReplyError):
        decode_sensors(_reply()[:46])


@given(st.binary(min_size=47, max_size=47))
def test_a_random_reply_is_refused_or_decodes_to_its_own_bytes(raw: bytes) -> None:
    try:
        reply = decode_sensors(raw)
    except ChecksumError:
        assert raw[46] != reduce(xor, raw[:46], 0)
        return
    again = struct.pack("<8h8h4HBhhB", *reply.proximity, *reply.ambient, *reply.microphones,
                        raw[40], *reply.steps, reply.tv_remote)  # fmt: skip
    assert again == raw[:46]


def test_setting_the_step_counters_is_a_one_shot_that_keeps_the_speeds() -> None:
    state = ActuatorPacket(speed_left=300, speed_right=300)
    after, first = fold(state, Request(Command.SET_STEPS, (5, -5)))
    assert after == state  # the speeds stay (gumstix.c:240-246)
    assert first is not None and first.settings == Settings.SET_STEP_COUNTERS
    assert encode_actuators(first)[:4] == bytes([5, 0, 0xFB, 0xFF])


def test_york_words_are_two_complement_and_only_changes_are_written() -> None:
    before = york.YorkState()
    after = before.with_speeds(-1, 1000).with_led(9, 1).with_led(3, 1)
    assert york.writes(after, before) == [
        (york.LEDS_RING, 0x08, False),
        (york.LEDS_FRONT_BODY, york.FRONT_BIT, False),
        (york.SPEED_LEFT, 0xFFFF, True),
        (york.SPEED_RIGHT, 1000, True),
    ]
    assert york.signed(0xFFFF) == -1 and york.signed(0x8000) == -32768


def test_york_refuses_what_its_firmware_would_clamp() -> None:
    with pytest.raises(OutOfRangeError, match="1000"):
        york.YorkState().with_speeds(1001, 0)
