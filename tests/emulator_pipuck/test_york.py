"""The e-puck1 with York's Pi-puck firmware: 16-bit registers at 0x1F read and written
with SMBus byte and word calls (yorkrobotlab/pi-puck-e-puck1, i2c_slave.c, main.c)."""

from __future__ import annotations

import struct


def test_word_registers_are_little_endian_and_speeds_clamp_to_1000(epuck1, client_of):
    client = client_of(epuck1)
    client("bus(12).write_word_data(0x1F, 2, 0x0203)")  # 515 steps/s, low byte first
    assert epuck1.truth.speeds == (515, 0)
    # On the wire: register, low byte, high byte (i2c_slave.c:59-76).
    assert client("raw_fd(12, 0x1F, [3, 0x2C, 0x01], 0)") == []
    assert epuck1.truth.speeds == (515, 300)
    client("bus(12).write_word_data(0x1F, 2, 0x8000)")  # -32768
    assert epuck1.truth.speeds == (-1000, 300)  # main.c:59-66
    assert client("bus(12).read_word_data(0x1F, 2)") == (-1000) & 0xFFFF  # written back
    assert client("raw_fd(12, 0x1F, [3], 2)") == [0x2C, 0x01]


def test_a_byte_write_clears_the_high_byte_and_reads_stop_after_two(epuck1, client_of):
    client = client_of(epuck1)
    client("bus(12).write_word_data(0x1F, 40, 0xBEEF)")  # a spare register keeps it
    assert client("bus(12).read_word_data(0x1F, 40)") == 0xBEEF
    client("bus(12).write_byte_data(0x1F, 40, 0x12)")  # i2c_slave.c:65-71
    assert client("bus(12).read_word_data(0x1F, 40)") == 0x0012
    assert client("bus(12).read_i2c_block_data(0x1F, 40, 4)") == [0x12, 0, 0xFF, 0xFF]
    assert client("bus(12).read_byte_data(0x1F, 40)") == 0x12


def test_leds_follow_registers_0_and_1(epuck1, client_of):
    client = client_of(epuck1)
    client("bus(12).write_byte_data(0x1F, 0, 0b10000101)")
    client("bus(12).write_byte_data(0x1F, 1, 0b11)")
    truth = epuck1.truth
    assert truth.red_leds == (True, False, True, False, False, False, False, True)
    assert truth.front_led and truth.body_led and not truth.last_was_stop
    client("bus(12).write_word_data(0x1F, 1, 0xFF02)")  # masked to 0x0003 (main.c:54)
    assert client("bus(12).read_word_data(0x1F, 1)") == 0x0002
    for register in (0, 1, 2, 3):
        client(f"bus(12).write_word_data(0x1F, {register}, 0)")
    assert epuck1.truth.last_was_stop and not any(epuck1.truth.red_leds)


def test_step_counters_are_unsigned_and_wrap(epuck1, client_of):
    client = client_of(epuck1)
    client("bus(12).write_word_data(0x1F, 3, 1000)")
    client("bus(12).write_word_data(0x1F, 2, -1000 & 0xFFFF)")
    epuck1.advance(0.5)
    left = client("bus(12).read_word_data(0x1F, 4)")
    right = client("bus(12).read_word_data(0x1F, 5)")
    assert 65536 - 520 < left < 65536 - 480 and 480 < right < 520  # 57600 // 1000 ticks
    assert (left, right) == epuck1.truth.steps


def test_ir_values_appear_once_enabled(epuck1, client_of):
    client = client_of(epuck1)
    words = "[bus(12).read_word_data(0x1F, r) for r in range(7, 23)]"
    before = client(words)
    assert before == [0] * 8 + [4095] * 8  # the ADC arrays start at 0
    client("bus(12).write_byte_data(0x1F, 6, 1)")
    assert epuck1.truth.ir_enabled
    after = client(words)
    world = epuck1.world
    assert after[:8] == world.proximity()
    assert after[8:] == [4095 - v for v in world.light()]  # higher is brighter
    assert struct.pack("<H", after[8])[0] == after[8] & 0xFF


def test_the_lsm330_is_powered_down_until_configured(epuck1, client_of):
    client = client_of(epuck1)
    assert client("raw_fd(12, 0x1E, [0x0F], 1)") == [0x40]  # WHO_AM_I_A
    assert client("raw_fd(12, 0x6A, [0x0F], 1)") == [0xD4]  # WHO_AM_I_G
    assert client("raw_fd(12, 0x1E, [0x28 | 0x80], 6)") == [0] * 6
    client("raw_fd(12, 0x1E, [0x20, 0x9F], 0)")  # e-puck1_imu.c:70-71
    client("raw_fd(12, 0x6A, [0x20, 0xCF], 0)")  # e-puck1_imu.c:82-83
    acc = struct.unpack("<3h", bytes(client("raw_fd(12, 0x1E, [0x28 | 0x80], 6)")))
    assert abs(acc[2] - 16384) < 50 and abs(acc[0]) < 50 and abs(acc[1]) < 50
    client("bus(12).write_word_data(0x1F, 3, 1000)")  # turn left on the spot
    epuck1.advance(0.01)
    gyro = struct.unpack("<3h", bytes(client("raw_fd(12, 0x6A, [0x28 | 0x80], 6)")))
    dps = gyro[2] * 8.75 / 1000
    assert 100 < dps < 200, gyro  # (1000 steps/s * 0.128 mm) / 52 mm, in deg/s


def crc8(data: bytes) -> int:
    """SMBus PEC: CRC-8, x^8 + x^2 + x + 1."""
    crc = 0
    for byte in data:
        crc ^= byte
        for _ in range(8):
            crc = (crc << 1 ^ 0x07) & 0xFF if crc & 0x80 else crc << 1 & 0xFF
    return crc


def test_pec_is_checked_on_reads_and_appended_to_writes(epuck1, client_of):
    # i2c-core-smbus.c: with I2C_PEC a read_byte_data reads one more byte and checks it.
    client = client_of(epuck1)
    good = crc8(bytes([0x1F << 1, 40, 0x1F << 1 | 1, 0x12]))
    client(f"bus(12).write_word_data(0x1F, 40, {good << 8 | 0x12})")
    client(f"bus(12).write_word_data(0x1F, 41, {(good ^ 1) << 8 | 0x12})")
    client("bus(12).enable_pec()")
    assert client("bus(12).read_byte_data(0x1F, 40)") == 0x12
    assert client("bus(12).read_byte_data(0x1F, 41)") == {"errno": "EBADMSG"}
    # A byte write with PEC sends register, value, PEC: York's firmware stores the PEC
    # as the high byte (i2c_slave.c:72-76).
    client("bus(12).write_byte_data(0x1F, 42, 0x34)")
    client("bus(12).enable_pec(False)")
    pec = crc8(bytes([0x1F << 1, 42, 0x34]))
    assert client("bus(12).read_word_data(0x1F, 42)") == pec << 8 | 0x34
