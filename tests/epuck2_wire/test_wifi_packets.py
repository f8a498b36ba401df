"""The e-puck2 radio's TCP packets: the 21-byte command, the reply stream, the image.

Vectors are written by hand from ESP = eshjordan/esp-idf@18f3ae6,
Projects/ESP32_E-Puck_2/main/socket_e-puck2.c and uart_e-puck2.c.
"""

from __future__ import annotations

import itertools
import re

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ego.backends.epuck2.wifi_packets import (
    CLOSED,
    NEED_DATA,
    Closed,
    EmptyReply,
    ImageReply,
    NeedData,
    Reply,
    ReplyParser,
    Request,
    SensorReply,
    encode_command,
    image_to_rgb888,
)
from ego.errors import FrameError, OutOfRangeError
from ego.serial.asercom2 import ActuatorEncoder, Actuators, Sound, encode_actuators

IMAGE_BYTES = 160 * 120 * 2  # socket_e-puck2.c:29 MAX_BUFF_SIZE 38400


def sensor_payload(button: int = 1, selector: int = 15) -> bytes:
    """104 bytes: zeros but the selector (byte 89), the button (102, uart_e-puck2.c:138)
    and the reserved byte moved to 103 (uart_e-puck2.c:142)."""
    out = bytearray(104)
    out[89] = selector
    out[102] = button
    return bytes(out)


def image_payload() -> bytes:
    return bytes((i * 7) & 0xFF for i in range(IMAGE_BYTES))


def stream() -> bytes:
    """Image then sensors (socket_e-puck2.c:191-192, 228-231), then an empty reply."""
    return b"\x01" + image_payload() + b"\x02" + sensor_payload() + b"\x03"


def drain(parser: ReplyParser) -> list[Reply | Closed]:
    events: list[Reply | Closed] = []
    while True:
        event = parser.next_event()
        if isinstance(event, NeedData):
            return events
        events.append(event)
        if isinstance(event, Closed):
            return events


def check_stream_events(events: list[Reply | Closed]) -> None:
    image, sensors, empty = events
    assert isinstance(image, ImageReply) and image.data == image_payload()
    assert isinstance(sensors, SensorReply) and sensors.data == sensor_payload()
    assert sensors.sensors.button is True and sensors.sensors.selector == 15
    assert isinstance(empty, EmptyReply)


# -- the command ---------------------------------------------------------------------------


def test_a_command_is_0x80_the_request_then_the_actuator_payload() -> None:
    payload = encode_actuators(Actuators(speed_left=-200))
    packet = encode_command(Request.IMAGE | Request.SENSORS, payload)
    assert len(packet) == 21  # ACTUATORS_BUFF_LEN 21 (socket_e-puck2.h:14)
    assert packet[0] == 0x80 and packet[1] == 0x03
    assert packet[2:] == payload  # memcpy(&uart_tx_buff[2], &buff[2], 19) (uart_e-puck2.c:46)
    assert packet[3:5] == bytes([0x38, 0xFF])  # command byte n is rx_buff[n-2]


def test_request_zero_asks_for_the_empty_reply() -> None:
    assert encode_command(Request(0), bytes(19))[:2] == b"\x80\x00"


def test_the_sound_byte_is_the_commands_last_and_goes_out_once() -> None:
    encoder = ActuatorEncoder()
    encoder.play(Sound.STAR_WARS)
    first = encode_command(Request.SENSORS, encoder.next_payload())
    second = encode_command(Request.SENSORS, encoder.next_payload())
    assert (first[20], second[20]) == (0x04, 0x00)


@pytest.mark.parametrize(("request_", "payload"), [(4, bytes(19)), (1, bytes(18)), (-1, bytes(19))])
def test_a_bad_command_is_refused(request_: int, payload: bytes) -> None:
    with pytest.raises(OutOfRangeError):
        encode_command(Request(request_) if 0 <= request_ < 4 else request_, payload)  # type: ignore[arg-type]


# -- the reply stream ------------------------------------------------------------------------


def test_nothing_buffered_needs_data() -> None:
    parser = ReplyParser()
    assert parser.next_event() is NEED_DATA
    parser.receive_data(b"\x01" + bytes(100))
    assert parser.next_event() is NEED_DATA and parser.buffered == 101


def test_the_stream_fed_byte_by_byte() -> None:
    parser = ReplyParser()
    events: list[Reply | Closed] = []
    for byte in stream():
        parser.receive_data(bytes([byte]))
        events += drain(parser)
    check_stream_events(events)
    assert parser.buffered == 0


@settings(max_examples=60, deadline=None)
@given(cuts=st.lists(st.integers(0, len(stream())), max_size=40))
def test_the_stream_fed_in_random_chunks(cuts: list[int]) -> None:
    data = stream()
    bounds = [0, *sorted(cuts), len(data)]
    parser = ReplyParser()
    events: list[Reply | Closed] = []
    for start, end in itertools.pairwise(bounds):
        if start == end:
            continue  # recv() returns b"" only at the end of the stream
        parser.receive_data(data[start:end])
        events += drain(parser)
    check_stream_events(events)


def test_a_clean_end_of_stream_is_closed() -> None:
    parser = ReplyParser()
    parser.receive_data(b"\x03")
    parser.receive_data(b"")
    assert isinstance(parser.next_event(), EmptyReply)
    assert parser.next_event() is CLOSED


@pytest.mark.parametrize("header", [0x00, 0x04, 0x80, 0xFF])
def test_an_unknown_header_is_refused_and_the_parser_stays_broken(header: int) -> None:
    parser = ReplyParser()
    parser.receive_data(bytes([header]) + b"\x03")
    with pytest.raises(FrameError, match=f"header 0x{header:02X} is not 0x01"):
        parser.next_event()
    with pytest.raises(FrameError):
        parser.next_event()
    with pytest.raises(FrameError):
        parser.receive_data(b"\x03")


def test_an_unknown_header_after_a_good_packet_is_refused() -> None:
    parser = ReplyParser()
    parser.receive_data(b"\x02" + sensor_payload() + b"\x05")
    assert isinstance(parser.next_event(), SensorReply)
    with pytest.raises(FrameError, match="header 0x05"):
        parser.next_event()


@pytest.mark.parametrize(
    ("data", "what"),
    [
        (b"\x01" + bytes(38399), "inside image reply (38399 of 38400 bytes)"),
        (b"\x02" + bytes(103), "inside sensors reply (103 of 104 bytes)"),
    ],
)
def test_a_stream_ending_inside_a_packet_is_refused(data: bytes, what: str) -> None:
    parser = ReplyParser()
    parser.receive_data(data)
    assert parser.next_event() is NEED_DATA
    parser.receive_data(b"")
    with pytest.raises(FrameError, match=re.escape(what)):
        parser.next_event()


def test_data_after_the_end_is_refused() -> None:
    parser = ReplyParser()
    parser.receive_data(b"")
    with pytest.raises(FrameError, match="after the end"):
        parser.receive_data(b"\x03")


def test_a_sensor_packet_with_bytes_the_firmware_never_sends_is_a_frame_error() -> None:
    parser = ReplyParser()
    parser.receive_data(b"\x02" + sensor_payload(button=7))
    with pytest.raises(FrameError, match="button byte 7"):
        parser.next_event()


# -- the image -------------------------------------------------------------------------------


def test_the_image_is_rgb565_big_endian() -> None:
    # First byte RRRRRGGG: red 0xF800, green 0x07E0, blue 0x001F, sent high byte first.
    pixels = [b"\xf8\x00", b"\x07\xe0", b"\x00\x1f", b"\xff\xff"]
    raw = b"".join(pixels) + bytes(IMAGE_BYTES - 8)
    rgb = image_to_rgb888(raw)
    assert rgb.shape == (120, 160, 3) and rgb.dtype == np.uint8
    assert rgb[0, :4].tolist() == [[255, 0, 0], [0, 255, 0], [0, 0, 255], [255, 255, 255]]
    assert rgb[1:].max() == 0 and rgb[0, 4:].max() == 0


def test_the_image_goes_through_the_exact_tables() -> None:
    # One mid-range code: R=10, G=33, B=17 -> round(i * 255 / 31 or 63) (thesis fig. 4.7).
    code = (10 << 11) | (33 << 5) | 17
    raw = code.to_bytes(2, "big") * (IMAGE_BYTES // 2)
    rgb = image_to_rgb888(raw)
    expected = [round(10 * 255 / 31), round(33 * 255 / 63), round(17 * 255 / 31)]
    assert rgb[119, 159].tolist() == expected and rgb[0, 0].tolist() == expected


def test_an_image_of_the_wrong_size_is_refused() -> None:
    with pytest.raises(FrameError, match="38400 bytes, not 38398"):
        image_to_rgb888(bytes(IMAGE_BYTES - 2))
