"""Asercom v2's binary commands over USB (selector 8) on a real pty: each reply's size and
content against the world, from MAIN:src/epuck1x/Asercom2.c (cited per test)."""

from __future__ import annotations

import math
import struct

import pytest
import serial
from epuck2_wire import ask_serial, batch, neg, parse_sensors, read_quiet, sync

from firmware_sim.epuck2 import Epuck2Emulator
from firmware_sim.world import Pose

#: Reply sizes of the commands that take no argument (Asercom2.c line ranges).
REPLY_SIZES = [
    (0x08, 103),  # 296-468: all sensors
    ("a", 6),  # 727-746
    ("A", 12),  # 748-782: three floats
    ("b", 2),  # 784-789
    ("E", 4),  # 815-820
    ("g", 6),  # 822-839
    ("I", 3 + 40 * 40 * 2),  # 841-851: mode, width, height, then 40x40 RGB565
    ("M", 8),  # 874-894: 3 ground + 1 cliff
    ("N", 16),  # 895-901
    ("O", 16),  # 902-908
    ("Q", 4),  # 934-941
    ("t", 1),  # 943-949
    ("u", 6),  # 951-963: three microphones
    (0x0B, 1),  # 590-592: button
    (0x0C, 8),  # 594-610: four microphones
    (0x0D, 2),  # 612-621: ToF
    (0x0E, 1),  # 623-631: SD card
]


@pytest.mark.parametrize(("code", "size"), REPLY_SIZES, ids=[str(c) for c, _ in REPLY_SIZES])
def test_each_command_answers_its_size(port: serial.Serial, code: int | str, size: int) -> None:
    reply = ask_serial(port, batch(code), size)
    assert len(reply) == size
    assert read_quiet(port, 0.1) == b"", "nothing may follow the reply"


def test_replies_of_a_batch_come_concatenated_at_its_end(port: serial.Serial) -> None:
    reply = ask_serial(port, batch("E", "Q", 0x0D), 4 + 4 + 2)
    assert len(reply) == 10
    assert read_quiet(port, 0.1) == b""


@pytest.mark.parametrize("code", [0x0F, 0x10, 0x11])
def test_switches_answer_one_zero_byte(port: serial.Serial, code: int) -> None:
    # Asercom2.c:633-725: one argument byte, then `buffer[i++] = 0; // success`.
    assert ask_serial(port, batch(code, bytes([1])), 1) == b"\x00"
    assert read_quiet(port, 0.1) == b""


def test_commands_without_reply_send_nothing(port: serial.Serial) -> None:
    # -'U' (964-975 commented out), -'D' (791-814), -'L', -'P', -0x0A: no bytes at all.
    port.write(batch("U", "D", bytes(4), "L", bytes([0, 0]), "P", bytes(4), 0x0A, bytes(12)))
    assert read_quiet(port, 0.3) == b""


def test_negative_speed_keeps_its_sign_and_e_echoes_16_bits(
    port: serial.Serial, usb: Epuck2Emulator
) -> None:
    port.write(batch("D", struct.pack("<hh", -200, 350)))
    reply = ask_serial(port, batch("E"), 4)
    assert struct.unpack("<hh", reply) == (-200, 350)
    assert usb.world.speeds == (-200, 350)


def test_speed_is_clamped_at_1100_but_e_reports_what_was_asked(
    port: serial.Serial, usb: Epuck2Emulator
) -> None:
    # motors.h:7 MOTOR_SPEED_LIMIT 1100; motors.c:300-305 clamps, E prints the static.
    port.write(batch("D", struct.pack("<hh", 1500, -1500)))
    assert struct.unpack("<hh", ask_serial(port, batch("E"), 4)) == (1500, -1500)
    assert usb.world.speeds == (1100, -1100)


def test_wheels_really_step_at_the_f407_timer_rate(usb: Epuck2Emulator) -> None:
    # motors.c:324: interval = 100000 / (2 v) ticks, one microstep each, 2 a step.
    usb.world.set_speeds(600, 600)
    vx, vy, _ = usb.world.velocity()
    metres_per_step = 2 * math.pi * 0.0205 / 1000
    assert math.hypot(vx, vy) / metres_per_step == pytest.approx(100000 / 83 / 2)


def test_odd_led_sets_only_its_red_channel_at_ten_percent(
    port: serial.Serial, usb: Epuck2Emulator
) -> None:
    # e_led.c:31-37: set_rgb_led(n, value*10, 0, 0): green and blue are cleared.
    port.write(batch(0x0A, bytes([50, 60, 70] * 4)))
    port.write(batch("L", bytes([1, 1])))
    sync(port)
    assert usb.robot.leds.rgb[0] == [10, 0, 0]
    assert usb.robot.leds.rgb[1] == [50, 60, 70]
    port.write(batch("L", bytes([3, 2])))  # toggle: lit (50) -> off
    sync(port)
    assert usb.robot.leds.rgb[1] == [0, 60, 70]


def test_binary_l_8_and_9_are_body_and_front(port: serial.Serial, usb: Epuck2Emulator) -> None:
    # Asercom2.c:862-872.
    port.write(batch("L", bytes([8, 1]), "L", bytes([9, 1])))
    sync(port)
    assert (usb.robot.leds.body, usb.robot.leds.front) == (True, True)
    assert usb.robot.leds.red == [False] * 4


def test_set_and_read_the_step_counters(port: serial.Serial) -> None:
    port.write(batch("P", struct.pack("<hh", 1234, -5)))
    assert struct.unpack("<hh", ask_serial(port, batch("Q"), 4)) == (1234, -5)


def test_temperature_command_always_answers_zero(port: serial.Serial, usb: Epuck2Emulator) -> None:
    # Asercom2.c:943-949: `if (gumstix_connected == 0) buffer[i++] = 0;`
    assert ask_serial(port, batch("t"), 1) == b"\x00"
    sensors = parse_sensors(ask_serial(port, batch(0x08), 103))
    assert sensors.temperature != 0  # the all-sensors packet has the IMU's


def test_all_sensors_describe_a_robot_at_rest(port: serial.Serial) -> None:
    s = parse_sensors(ask_serial(port, batch(0x08), 103))
    # e_acc.c:17-32: centred on 0, about 768 a g, z up.
    assert abs(s.acc[0]) <= 2 and abs(s.acc[1]) <= 2
    assert s.acc[2] == 768
    assert s.acc_magnitude == pytest.approx(768, abs=3)
    assert s.selector == 8
    assert s.magnetometer == (0.0, 0.0, 0.0)  # not set up over USB
    assert s.ground == (0, 0, 0)  # ground.c:66-86: no module, values stay 0
    assert s.byte102 == 0


def test_accelerometer_raw_is_centred_on_2048(port: serial.Serial) -> None:
    # e_acc.c:34-50 (-'a', ASCII A): no offsets, + 2048.
    x, y, z = struct.unpack("<3h", ask_serial(port, batch("a"), 6))
    assert (abs(x - 2048) <= 2, abs(y - 2048) <= 2, z) == (True, True, 2048 + 768)


def test_gyro_follows_the_turning_rate(port: serial.Serial, usb: Epuck2Emulator) -> None:
    port.write(batch("D", struct.pack("<hh", 500, -500)))  # spin clockwise
    sync(port)
    _, _, z = struct.unpack("<3h", ask_serial(port, batch("g"), 6))
    expected = math.degrees(usb.world.velocity()[2]) * 32768 / 250  # imu.c:333, +-250 dps
    assert expected < -10000
    assert z == pytest.approx(expected, abs=3)


def test_magnetometer_reads_once_switched_on(port: serial.Serial) -> None:
    ask_serial(port, batch(0x0F, bytes([1])), 1)
    field = parse_sensors(ask_serial(port, batch(0x08), 103)).magnetometer
    assert math.hypot(*field) > 20  # tens of microtesla


def test_tof_measures_the_wall_ahead(port: serial.Serial, usb: Epuck2Emulator) -> None:
    usb.world.place(Pose(0.3, 0.0, 0.0))  # facing the wall at x = 0.5
    usb.world.advance(usb.world.clock() + 0.2)
    read_quiet(port, 0.15)  # the sensor is read every 100 ms (VL53L0X.c:51)
    (mm,) = struct.unpack("<H", ask_serial(port, batch(0x0D), 2))
    assert mm == pytest.approx((0.5 - 0.3 - 0.0375) * 1000, abs=2)


def test_tof_stopped_keeps_its_last_value(port: serial.Serial, usb: Epuck2Emulator) -> None:
    usb.world.place(Pose(0.3, 0.0, 0.0))
    read_quiet(port, 0.15)
    (before,) = struct.unpack("<H", ask_serial(port, batch(0x0D), 2))
    ask_serial(port, batch(0x11, bytes([0])), 1)
    usb.world.place(Pose(0.0, 0.0, 0.0))
    read_quiet(port, 0.15)
    (after,) = struct.unpack("<H", ask_serial(port, batch(0x0D), 2))
    assert after == before


def test_proximity_sees_a_wall_in_front_only(port: serial.Serial, usb: Epuck2Emulator) -> None:
    usb.world.place(Pose(0.455, 0.0, 0.0))  # a few mm from the wall
    values = struct.unpack("<8H", ask_serial(port, batch("N"), 16))
    assert min(values[0], values[7]) > 500
    assert max(values[3], values[4]) < 50


def test_ground_module_gives_three_floor_values_and_a_cliff() -> None:
    from firmware_sim.world import World

    with Epuck2Emulator(World(seed=3, noise=False), ground_module=True) as emu:
        assert emu.pty_path is not None
        with serial.Serial(emu.pty_path, timeout=0.2) as p:
            read_quiet(p, 0.05)
            values = struct.unpack("<4H", ask_serial(p, batch("M"), 8))
            truth = emu.world.floor()
    assert list(values[:3]) == truth
    assert values[3] == 0


def test_w_lowercase_over_usb_hangs_the_firmware(port: serial.Serial) -> None:
    # Asercom2.c:992-1003: -'w' reads its bytes with e_getchar_uart1, the radio's UART,
    # which never receives anything while the robot talks over USB.
    port.write(bytes([neg("w")]) + bytes(40))
    port.write(b"V\r")
    assert read_quiet(port, 0.4) == b""


def test_image_is_rgb565_big_endian(port: serial.Serial, usb: Epuck2Emulator) -> None:
    from firmware_sim.camera import render_rgb888

    reply = ask_serial(port, batch("I"), 3 + 3200)
    assert reply[:3] == bytes([1, 40, 40])  # Asercom2.c:133-137, 845-847
    first = struct.unpack(">H", reply[3:5])[0]
    view = render_rgb888(usb.world, 40, 40, fov_rad=0.84 * 160 / 640)
    red = int(view[0, 0, 0])
    assert abs((first >> 11) * 255 / 31 - red) <= 9
