"""The e-puck2's "all sensors" (-0x08) reply, on bytes laid out by hand from the source.

Every vector here is written byte by byte at the offsets the firmware writes them,
MAIN = e-puck2/e-puck2_main-processor@d2e0dbb, src/epuck1x/Asercom2.c:296-468 (each
field ``n & 0xff`` then ``n >> 8``), never through ego's own layout.
"""

from __future__ import annotations

import struct

import pytest
from hypothesis import given
from hypothesis import strategies as st

from ego.errors import ExtraBytesError, ProtocolError, ShortReplyError
from ego.serial.asercom2 import SensorLayout, decode_sensors

# The offsets of docs/protocol.md's table, each from its lines of Asercom2.c.
ACC, MAG_F, ORIENT_F, INCL_F = 0, 6, 10, 14  # 307-312, 321-328, 330-337, 339-346
GYRO, MAGNET, TEMP = 18, 24, 36  # 351-356, 367-374, 378
PROX, AMBIENT, TOF, MICS = 37, 53, 69, 71  # 384-388, 391-395, 399-401, 408-419
STEPS, BATTERY, SD, TV, SELECTOR = 79, 83, 85, 86, 89  # 422-427, 430-432, 437, 444-446, 450
GROUND_PROX, GROUND_AMB, RESERVED = 90, 96, 102  # 453-457, 460-464, 467


def put16(buf: bytearray, offset: int, value: int) -> None:
    """As the firmware does: ``buffer[i++] = n & 0xff; buffer[i++] = n >> 8``."""
    buf[offset] = value & 0xFF
    buf[offset + 1] = (value >> 8) & 0xFF


def put_float(buf: bytearray, offset: int, value: float) -> None:
    """A float's bits, lowest byte first (Asercom2.c:321-328 copy the float's memory on a
    little-endian Cortex-M4; 369-373 shift its uint32 bits)."""
    buf[offset : offset + 4] = struct.pack("<f", value)


def sample_packet() -> bytearray:
    """A 103-byte USB/Bluetooth reply with a distinct value in every field."""
    buf = bytearray(103)
    for axis, value in enumerate((-5, 12, 768)):  # 768: about 1 g, centred on 0
        put16(buf, ACC + 2 * axis, value)
    put_float(buf, MAG_F, 768.5)
    put_float(buf, ORIENT_F, 181.25)
    put_float(buf, INCL_F, 2.5)
    for axis, value in enumerate((-131, 262, -1)):
        put16(buf, GYRO + 2 * axis, value)
    for axis, field in enumerate((-20.5, 31.25, 0.125)):
        put_float(buf, MAGNET + 4 * axis, field)
    buf[TEMP] = (-3) & 0xFF  # signed char getTemperature()
    for k in range(8):
        put16(buf, PROX + 2 * k, 100 + k)
        put16(buf, AMBIENT + 2 * k, 3000 + k)
    put16(buf, TOF, 2000)
    for k in range(4):
        put16(buf, MICS + 2 * k, 10 + k)
    put16(buf, STEPS, -1234)
    put16(buf, STEPS + 2, 32767)
    put16(buf, BATTERY, 3500)
    buf[SD] = 1
    buf[TV], buf[TV + 1], buf[TV + 2] = 1, 7, 42
    buf[SELECTOR] = 8
    for k in range(3):
        put16(buf, GROUND_PROX + 2 * k, 500 + k)
        put16(buf, GROUND_AMB + 2 * k, 900 + k)
    buf[RESERVED] = 0  # "Additional empty byte for future use"
    return buf


def wifi_from_serial(serial: bytes, button: int) -> bytes:
    """ESP:uart_e-puck2.c:137-142: byte 102 becomes the button, the reserved byte moves
    to 103."""
    out = bytearray(serial) + b"\x00"
    temp = out[102]
    out[102] = button
    out[103] = temp
    return bytes(out)


def test_every_field_is_read_at_its_firmware_offset() -> None:
    packet = decode_sensors(bytes(sample_packet()), SensorLayout.SERIAL)
    assert packet.acceleration == (-5, 12, 768)
    assert packet.acceleration_magnitude == 768.5
    assert packet.orientation_deg == 181.25
    assert packet.inclination_deg == 2.5
    assert packet.gyro == (-131, 262, -1)
    assert packet.magnetic_field_ut == (-20.5, 31.25, 0.125)
    assert packet.temperature_c == -3
    assert packet.proximity == tuple(range(100, 108))
    assert packet.ambient == tuple(range(3000, 3008))
    assert packet.tof_mm == 2000
    assert packet.microphones == (10, 11, 12, 13)
    assert packet.steps == (-1234, 32767)
    assert packet.battery_raw == 3500
    assert packet.sd_card_ok is True
    assert packet.tv_remote == (1, 7, 42)
    assert packet.selector == 8
    assert packet.ground_proximity == (500, 501, 502)
    assert packet.ground_ambient == (900, 901, 902)
    assert packet.button is None  # USB/Bluetooth carry no button in -0x08


def test_accelerometer_is_centred_on_zero_not_2048() -> None:
    # e_get_acc (e_acc.c:17-32) has no +2048: a robot lying flat reads (0, 0, ~768).
    # Webots' WiFi wrapper's k*(raw-2000) would make 0 into -2000 counts.
    buf = sample_packet()
    for axis, value in enumerate((0, -768, 768)):
        put16(buf, ACC + 2 * axis, value)
    assert decode_sensors(bytes(buf), SensorLayout.SERIAL).acceleration == (0, -768, 768)


def test_the_wifi_packet_is_the_serial_one_with_the_button_moved_in() -> None:
    serial = bytes(sample_packet())
    for button in (0, 1):
        wifi = decode_sensors(wifi_from_serial(serial, button), SensorLayout.WIFI)
        assert wifi.button is bool(button)
        same = decode_sensors(serial, SensorLayout.SERIAL)
        assert [getattr(wifi, f) for f in wifi.__slots__ if f != "button"] == [
            getattr(same, f) for f in same.__slots__ if f != "button"
        ]


def test_103_and_104_bytes_are_not_interchangeable() -> None:
    serial = bytes(sample_packet())
    wifi = wifi_from_serial(serial, 1)
    with pytest.raises(ExtraBytesError, match="103 bytes, got 104"):
        decode_sensors(wifi, SensorLayout.SERIAL)
    with pytest.raises(ShortReplyError, match="104 bytes, got only 103"):
        decode_sensors(serial, SensorLayout.WIFI)


def test_a_short_reply_is_refused() -> None:
    with pytest.raises(ShortReplyError, match="got only 102"):
        decode_sensors(bytes(sample_packet())[:102], SensorLayout.SERIAL)


@pytest.mark.parametrize(
    ("offset", "value", "what"),
    [(RESERVED, 1, "reserved byte 1"), (SELECTOR, 16, "selector 16"), (SD, 2, "SD card byte 2")],
)
def test_bytes_the_firmware_never_sends_mean_the_stream_is_out_of_step(
    offset: int, value: int, what: str
) -> None:
    buf = sample_packet()
    buf[offset] = value
    with pytest.raises(ProtocolError, match=what):
        decode_sensors(bytes(buf), SensorLayout.SERIAL)


def test_a_wifi_button_byte_other_than_0_or_1_is_refused() -> None:
    with pytest.raises(ProtocolError, match="button byte 2"):
        decode_sensors(wifi_from_serial(bytes(sample_packet()), 2), SensorLayout.WIFI)


u16 = st.integers(0, 0xFFFF)
i16 = st.integers(-0x8000, 0x7FFF)


@given(
    acc=st.tuples(i16, i16, i16),
    prox=st.lists(u16, min_size=8, max_size=8),
    steps=st.tuples(i16, i16),
    tof=u16,
    selector=st.integers(0, 15),
    temperature=st.integers(-128, 127),
)
def test_hand_packed_values_come_back(
    acc: tuple[int, int, int],
    prox: list[int],
    steps: tuple[int, int],
    tof: int,
    selector: int,
    temperature: int,
) -> None:
    buf = sample_packet()
    for axis, value in enumerate(acc):
        put16(buf, ACC + 2 * axis, value)
    for k, value in enumerate(prox):
        put16(buf, PROX + 2 * k, value)
    put16(buf, STEPS, steps[0])
    put16(buf, STEPS + 2, steps[1])
    put16(buf, TOF, tof)
    buf[SELECTOR] = selector
    buf[TEMP] = temperature & 0xFF
    packet = decode_sensors(bytes(buf), SensorLayout.SERIAL)
    assert (packet.acceleration, packet.proximity, packet.steps) == (acc, tuple(prox), steps)
    assert (packet.tof_mm, packet.selector, packet.temperature_c) == (tof, selector, temperature)


@given(st.binary(min_size=103, max_size=103))
def test_random_bytes_decode_or_raise_a_protocol_error(raw: bytes) -> None:
    try:
        packet = decode_sensors(raw, SensorLayout.SERIAL)
    except ProtocolError:
        return
    assert 0 <= packet.selector <= 15
