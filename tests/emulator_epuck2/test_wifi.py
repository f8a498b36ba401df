"""The radio's WiFi protocol on a real loopback socket (ESP:Projects/ESP32_E-Puck_2/main/
socket_e-puck2.c and uart_e-puck2.c, MAIN:src/epuck1x/Asercom2.c:470-571): the command
packet's fields, the replies, and the streaming."""

from __future__ import annotations

import struct

import numpy as np
from epuck2_wire import WifiClient, command, parse_sensors
from helpers import wait_for_more

from firmware_sim.camera import render_rgb888
from firmware_sim.epuck2 import Epuck2Emulator

SENSORS, IMAGE = 0x02, 0x01


def test_nothing_is_sent_before_a_valid_command(wifi: Epuck2Emulator, client: WifiClient) -> None:
    # socket_e-puck2.c:182: `if(valid_cmd_received == 1)` guards every send.
    assert wifi.radio is not None
    assert wait_for_more(lambda: wifi.radio.loops, 20)  # 20 chances to send
    assert client.nothing_pending()
    client.send(command(0))
    assert client.reply() == (0x03, b"")


def test_the_last_command_is_reapplied_and_answered_every_loop(client: WifiClient) -> None:
    client.send(command(SENSORS))
    for _ in range(4):  # one command, a stream of answers (socket_e-puck2.c:145-279)
        client.sensors()


def test_sensor_packet_is_the_all_sensors_reply_plus_the_button(
    wifi: Epuck2Emulator, client: WifiClient
) -> None:
    wifi.robot.button = True
    client.send(command(SENSORS))
    client.sensors()  # the first buffer was filled before the button went down
    s = client.sensors()
    assert s.byte102 == 1  # uart_e-puck2.c:137-142
    assert s.selector == 15
    # e_acc.c:17-32: centred on 0, ~768 a g (not 2048 like -'a').
    assert abs(s.acc[0]) <= 2 and abs(s.acc[1]) <= 2 and s.acc[2] == 768
    assert s.magnetometer != (0.0, 0.0, 0.0)  # main.c:850 sets it up in selector 15


def test_sensor_packet_ends_with_the_reserved_byte(client: WifiClient) -> None:
    client.send(command(SENSORS))
    header, payload = client.reply()
    assert (header, len(payload), payload[103]) == (SENSORS, 104, 0)


def test_image_then_sensors_when_both_are_asked(client: WifiClient) -> None:
    client.send(command(IMAGE | SENSORS))
    first, image = client.reply()
    second, _ = client.reply()
    assert (first, len(image), second) == (IMAGE, 38400, SENSORS)


def test_image_is_160_by_120_rgb565_big_endian(wifi: Epuck2Emulator, client: WifiClient) -> None:
    client.send(command(IMAGE))
    header, image = client.reply()
    assert header == IMAGE
    rgb = render_rgb888(wifi.world, 160, 120).astype(np.uint32)  # the robot stands still
    codes = ((rgb[..., 0] * 31 + 127) // 255) << 11
    codes |= ((rgb[..., 1] * 63 + 127) // 255) << 5
    codes |= (rgb[..., 2] * 31 + 127) // 255
    assert image == codes.astype(">u2").tobytes()
    assert image != codes.astype("<u2").tobytes()


def test_speeds_are_signed_little_endian_and_clamped(
    wifi: Epuck2Emulator, client: WifiClient
) -> None:
    client.send(command(SENSORS, left=-300, right=2000))
    client.sensors()
    client.sensors()
    assert wifi.world.speeds == (-300, 1100)


def test_leds_bits_and_rgb_in_percent_r_g_b(wifi: Epuck2Emulator, client: WifiClient) -> None:
    rgb = ((10, 20, 30), (0, 0, 100), (100, 0, 0), (1, 2, 3))
    client.send(command(SENSORS, leds=0b10_0101, rgb=rgb))
    client.sensors()
    client.sensors()
    leds = wifi.robot.leds
    assert leds.red == [True, False, True, False]
    assert (leds.body, leds.front) == (False, True)
    assert leds.rgb == [list(t) for t in rgb]  # Asercom2.c:547-550: R, G, B as sent


def test_settings_bit_2_pins_the_step_counters_and_keeps_the_speeds(
    wifi: Epuck2Emulator, client: WifiClient
) -> None:
    client.send(command(SENSORS, left=1000, right=1000))
    client.sensors()
    client.sensors()
    client.send(command(SENSORS, settings=0x04, left=1000, right=-2000))
    for _ in range(10):  # 200 ms or more: 200 steps at 1000 steps/s, were they not pinned
        client.sensors()
    left, right = client.sensors().steps
    assert wifi.world.speeds == (1000, 1000)  # motors.c:218-224: only the counters change
    # re-applied every loop: pinned within one loop's travel
    assert 1000 <= left < 1100 and -2000 <= right < -1900


def test_sound_sent_once_plays_once(wifi: Epuck2Emulator, client: WifiClient) -> None:
    client.send(command(0, sound=0x01) + command(0))  # the next command clears the bit
    for _ in range(6):
        client.reply()
    assert wifi.robot.sound_names() == ["mario"]


def test_a_held_sound_bit_restarts_every_loop(wifi: Epuck2Emulator, client: WifiClient) -> None:
    client.send(command(0, sound=0x04))
    for _ in range(5):
        client.reply()
    assert wifi.robot.sound_names().count("starwars") >= 4


def test_commands_are_applied_one_a_loop_up_to_four_queued(
    wifi: Epuck2Emulator, client: WifiClient
) -> None:
    assert wifi.radio is not None
    client.send(command(0))
    client.reply()
    client.send(b"".join(command(0, left=101 + i) for i in range(4)))
    for _ in range(8):
        client.reply()
    lefts = {struct.unpack("<h", p[1:3])[0] for p in wifi.radio.polls()}
    assert {101, 102, 103, 104} <= lefts


def test_five_queued_commands_are_flushed_to_the_last(
    wifi: Epuck2Emulator, client: WifiClient
) -> None:
    # socket_e-puck2.c:149: `rx_bytes_not_read >= ACTUATORS_BUFF_LEN*5`.
    assert wifi.radio is not None
    client.send(command(0))
    client.reply()
    client.send(b"".join(command(0, left=201 + i) for i in range(5)))
    for _ in range(6):
        client.reply()
    lefts = {struct.unpack("<h", p[1:3])[0] for p in wifi.radio.polls()}
    assert 205 in lefts
    assert not lefts & {201, 202, 203, 204}


def test_sensor_values_lag_two_packets(client: WifiClient) -> None:
    # uart_e-puck2.c:49-71: the buffer handed out was filled by the previous poll, and a
    # poll reads the sensors (-0x08) before it sets the actuators (-0x09, :89-90), so a
    # step counter pinned by this command shows in the third packet.
    client.send(command(SENSORS, settings=0x04, left=500))
    first, second, third = (client.sensors() for _ in range(3))
    assert (first.steps[0], second.steps[0]) == (0, 0)
    assert abs(third.steps[0] - 500) < 20


def test_first_packet_parses_with_the_usb_layout(client: WifiClient) -> None:
    client.send(command(SENSORS))
    _, payload = client.reply()
    assert parse_sensors(payload).temperature == 30
