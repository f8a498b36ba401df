"""Asercom v2's ASCII commands and the quirks of its line reader, over USB on a real pty
(MAIN:src/epuck1x/Asercom2.c:1063-1620)."""

from __future__ import annotations

import struct

import serial
from epuck2_wire import ask_serial, batch, read_quiet, say

from firmware_sim.epuck2 import Epuck2Emulator


def test_version_names_v2_and_the_hardware_word(port: serial.Serial) -> None:
    # Asercom2.c:1543-1559; DataEEPROM.c:5-7 returns 0xFFF7.
    assert say(port, b"V\r") == (b"v,Version 2.0 January 2018 GCtronic\r\nHW version: FFF7\r\n")


def test_lowercase_letters_are_accepted(port: serial.Serial) -> None:
    assert say(port, b"c\r") == b"c,8\r\n"  # 1084-1086: toupper unless b or g


def test_lf_after_cr_swallows_the_next_byte_even_a_binary_one(port: serial.Serial) -> None:
    # 1067-1070: the \n starts ASCII mode, which waits for the first byte that is not
    # \r or \n and makes it the first of a line; here that is -0x08.
    say(port, b"V\r\n")
    port.write(batch(0x08))
    assert read_quiet(port, 0.3) == b"", "the binary request was eaten into a line"
    assert say(port, b"\r") == b"z,Command not found\r\n"


def test_cr_alone_leaves_the_next_binary_request_alone(port: serial.Serial) -> None:
    say(port, b"V\r")
    assert len(ask_serial(port, batch(0x08), 103)) == 103


def test_ascii_e_prints_binary_speeds_unsigned(port: serial.Serial, usb: Epuck2Emulator) -> None:
    # 801, 811: speedl = (unsigned char)c1 + ((unsigned int)c2 << 8); 1147: "%d".
    port.write(batch("D", struct.pack("<hh", -200, 100)))
    assert say(port, b"E\r") == b"e,65336,100\r\n"
    assert usb.world.speeds == (-200, 100)  # e_motors.c:83 casts to int16 again


def test_ascii_d_is_signed_and_cast_to_16_bits(port: serial.Serial, usb: Epuck2Emulator) -> None:
    assert say(port, b"D,-300,70000\r") == b"d\r\n"
    assert say(port, b"E\r") == b"e,-300,70000\r\n"
    # 70000 as int16 is 4464, which the driver clamps to 1100.
    assert usb.world.speeds == (-300, 1100)


def test_a_missing_number_keeps_the_old_value(port: serial.Serial, usb: Epuck2Emulator) -> None:
    say(port, b"D,100,200\r")
    say(port, b"D,300\r")  # sscanf stops: speedr keeps 200
    assert usb.world.speeds == (300, 200)


def test_r_gets_no_answer(port: serial.Serial) -> None:
    # 1466-1473: the reply and the reset are commented out.
    port.write(b"R\r")
    assert say(port, b"C\r") == b"c,8\r\n"


def test_lowercase_t_is_the_sound_command(port: serial.Serial, usb: Epuck2Emulator) -> None:
    assert say(port, b"t,1\r") == b"t\r\n"
    assert usb.robot.sound_names() == ["mario"]
    assert say(port, b"T,0\r") == b"t\r\n"
    assert usb.robot.sound_names() == ["mario", "stop"]


def test_l_8_and_l_9_set_every_ring_led(port: serial.Serial, usb: Epuck2Emulator) -> None:
    # 1379-1380: e_set_led(8 or 9, ...) is e_led.c's default: all eight.
    assert say(port, b"L,9,1\r") == b"l\r\n"
    leds = usb.robot.leds
    assert leds.red == [True] * 4
    assert leds.rgb == [[10, 0, 0]] * 4
    assert (leds.body, leds.front) == (False, False)


def test_s_leaves_body_front_and_the_echoed_speeds(
    port: serial.Serial, usb: Epuck2Emulator
) -> None:
    say(port, b"B,1\r")
    say(port, b"F,1\r")
    say(port, b"L,0,1\r")
    say(port, b"D,300,-300\r")
    assert say(port, b"S\r") == b"s\r\n"
    leds = usb.robot.leds
    assert usb.world.speeds == (0, 0)
    assert (leds.body, leds.front, leds.red[0]) == (True, True, False)
    assert say(port, b"E\r") == b"e,300,-300\r\n"


def test_q_prints_the_32_bit_counters(port: serial.Serial) -> None:
    port.write(batch("P", struct.pack("<hh", -5, 7)))  # stored unsigned: 65531
    assert say(port, b"Q\r") == b"q,65531,7\r\n"
    assert struct.unpack("<hh", ask_serial(port, batch("Q"), 4)) == (-5, 7)


def test_a_prints_values_centred_on_2048(port: serial.Serial) -> None:
    x, y, z = (int(v) for v in say(port, b"A\r").decode().strip().split(",")[1:])
    assert abs(x - 2048) <= 2 and abs(y - 2048) <= 2 and z == 2816


def test_m_prints_three_ground_and_two_cliff_values(port: serial.Serial) -> None:
    assert say(port, b"M\r") == b"m,0,0,0,0,0\r\n"  # no module fitted


def test_b_prints_the_battery_raw_and_percentage(port: serial.Serial) -> None:
    # battery_level.h:14-18: 3.9 V through 220k/330k on a 3.0 V, 12-bit ADC.
    assert say(port, b"b\r") == b"b,3194 (62%)\r\n"


def test_unknown_letter_is_not_found(port: serial.Serial) -> None:
    assert say(port, b"X\r") == b"z,Command not found\r\n"


def test_k_calibrates_in_two_lines(port: serial.Serial) -> None:
    port.write(b"K\r")
    port.timeout = 5
    first = port.read_until(b"\n")
    assert first == b"k, Starting calibration - Remove any object in sensors range\r\n"
    assert read_quiet(port, 0.2) == b"", "the calibration takes its time"
    assert port.read_until(b"\n") == b"k, Calibration finished\r\n"


def test_help_lists_the_usb_commands(port: serial.Serial) -> None:
    text = say(port, b"H\r").decode()
    assert text.startswith("\n")
    assert '"V"       Version of SerCom\r\n' in text
    assert '"A"' not in text  # 1276: left out when isEpuckVersion1_3() is 1


def test_a_tv_remote_is_reported_but_never_drives(port: serial.Serial, usb: Epuck2Emulator) -> None:
    # Asercom2.c:229-285 would drive, but only while e_getchar_uart2 returns 0, and
    # chSequentialStreamRead blocks until a byte comes (e_uart_char.c:58-63).
    usb.remote_key(2)
    assert say(port, b"G\r") == b"g IR check : 0x0, address : 0x0, data : 0x2\r\n"
    assert usb.world.speeds == (0, 0)
    assert say(port, b"E\r") == b"e,0,0\r\n"
