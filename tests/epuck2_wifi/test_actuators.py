"""What the WiFi commands carry: the one-shot sound in exactly one command (the radio
re-applies the last command every loop, so a sound bit left set replays), negative
speeds with their sign, the LEDs' bytes."""

from __future__ import annotations

import struct

import pytest
from helpers import wait_for_more, wait_until

import ego
from ego.backends.epuck2.requests import WIFI_PROFILE
from ego.core.registry import open_port
from ego.errors import UnsupportedDeviceError
from ego.seam.batch import Batch, Request
from ego.seam.profile import Command, Firmware
from ego.serial.asercom2 import Actuators, Sound, encode_actuators
from ego.serial.profiles import PROFILES
from ego.serial.protocol import encode_batch
from firmware_sim.epuck2 import Epuck2Emulator


def batch(*requests: Request) -> Batch:
    return encode_batch(requests, WIFI_PROFILE)


def test_a_one_shot_sound_plays_once(wifi: Epuck2Emulator, url: str) -> None:
    payload = bytearray(encode_actuators(Actuators(speed_left=100, speed_right=100)))
    payload[18] = Sound.MARIO
    opened = open_port(url)
    try:
        arguments = WIFI_PROFILE.wire_format(Command.ALL_ACTUATORS).arguments.unpack(payload)
        opened.channel.exchange(batch(Request(Command.ALL_ACTUATORS, arguments)))
        for _ in range(10):  # steps go on; the radio loops many times meanwhile
            opened.channel.exchange(batch(Request(Command.PROXIMITY)))
        # And 20 more of the radio's loops: each passes the main processor the command
        # in force, and would play the sound again had the one-shot not been cleared.
        assert wifi.radio is not None
        assert wait_for_more(lambda: len(wifi.radio.polls()), 20)
    finally:
        opened.close()
    assert wifi.robot.sound_names().count("mario") == 1, wifi.robot.sound_names()
    assert wifi.radio is not None
    assert sum(1 for poll in wifi.radio.polls() if poll[18] == Sound.MARIO) == 1


def test_negative_speeds_keep_their_sign_on_the_wheels(wifi: Epuck2Emulator, url: str) -> None:
    with ego.Robot(url) as robot:
        robot.motors.set_speed(-300, 200)
        robot.step(16)
        assert wait_until(lambda: wifi.world.speeds == (-300, 200))
        robot.motors.set_speed(150, -1000)
        robot.step(16)
        assert wait_until(lambda: wifi.world.speeds == (150, -1000))


def test_get_speed_answers_signed_bytes(url: str) -> None:
    opened = open_port(url)
    try:
        b = batch(Request(Command.SET_SPEED, (-200, 7)), Request(Command.GET_SPEED))
        assert opened.channel.exchange(b) == struct.pack("<2h", -200, 7)
    finally:
        opened.close()


def test_the_leds_bytes(wifi: Epuck2Emulator, url: str) -> None:
    opened = open_port(url)
    try:
        opened.channel.exchange(batch(
            Request(Command.SET_LED, (0, 1)),  # LED1, red
            Request(Command.SET_LED, (3, 1)),  # LED4's red at 10 %, as -'L' over USB
            Request(Command.SET_LED, (8, 1)),  # body
            Request(Command.RGB_LEDS, (100, 0, 0, 0, 0, 0, 0, 50, 0, 0, 0, 100)),
        ))  # fmt: skip
        leds = wifi.robot.leds
        assert wait_until(lambda: leds.body)
        assert leds.red == [True, False, False, False]
        assert leds.rgb == [[100, 0, 0], [0, 0, 0], [0, 50, 0], [0, 0, 100]]
        assert not leds.front
    finally:
        opened.close()


def test_the_sensors_come_byte_exact_in_the_usb_layout(wifi: Epuck2Emulator, url: str) -> None:
    opened = open_port(url)
    try:
        reply = opened.channel.exchange(batch(Request(Command.ALL_SENSORS)))
        prox = opened.channel.exchange(batch(Request(Command.PROXIMITY), Request(Command.TOF)))
    finally:
        opened.close()
    assert len(reply) == 103 and reply[102] == 0  # the reserved byte, as over USB
    assert reply[89] == 15  # the selector: WiFi
    assert len(prox) == 18


def test_what_wifi_cannot_serve_is_refused_naming_the_transport(url: str) -> None:
    with ego.Robot(url) as robot:
        with pytest.raises(UnsupportedDeviceError, match=r"epuck2://.*ASCII"):
            robot.channel.ascii_command("V")
        e_puck1 = PROFILES[Firmware.GCTRONIC]  # U, which the e-puck2 never answers
        with pytest.raises(UnsupportedDeviceError, match=r"epuck2://.*mic_buffer"):
            robot.channel.exchange(encode_batch([Request(Command.MIC_BUFFER)], e_puck1))


def test_the_e_puck1_families_read_through_the_wifi_packet(wifi: Epuck2Emulator, url: str) -> None:
    # Every family a WiFi robot serves decodes the translated replies as over USB.
    with ego.Robot(url) as robot:
        for family in (robot.proximity, robot.light, robot.accelerometer, robot.encoders,
                       robot.microphones, robot.floor):  # fmt: skip
            family.enable(16)
        robot.motors.set_speed(200, 200)
        for _ in range(10):
            assert robot.step(16) == 0
        assert len(robot.proximity.values) == 8 and len(robot.light.values) == 8
        x, y, z = robot.accelerometer.values
        assert abs(z) > max(abs(x), abs(y))  # gravity, in the firmware's counts
        left, right = robot.encoders.values
        assert left > 0 and right > 0  # the wheels turned forward


def test_a_refused_batch_changes_nothing(wifi: Epuck2Emulator, url: str) -> None:
    opened = open_port(url)
    try:
        with pytest.raises(ego.errors.OutOfRangeError, match="LED 12"):
            opened.channel.exchange(
                batch(Request(Command.SET_SPEED, (500, 500)), Request(Command.SET_LED, (12, 1)))
            )
        reply = opened.channel.exchange(batch(Request(Command.GET_SPEED)))
    finally:
        opened.close()
    assert reply == struct.pack("<2h", 0, 0)
