"""The e-puck2's sensors follow the world (firmware_sim's worlds, ground truth from its
public methods): microphones, light, steps, battery, over USB on a real pty."""

from __future__ import annotations

import math
import struct

import serial
from epuck2_wire import ask_serial, batch, parse_sensors, sync

from firmware_sim.epuck2 import Epuck2Emulator
from firmware_sim.world import Pose


def _face(emu: Epuck2Emulator, x: float, y: float) -> None:
    """Stand at the centre, facing the point (x, y)."""
    emu.world.place(Pose(0.0, 0.0, math.atan2(y, x)))


def test_the_front_microphone_hears_a_source_ahead_best(
    port: serial.Serial, usb: Epuck2Emulator
) -> None:
    sound = usb.world.sound
    _face(usb, sound.x_m, sound.y_m)
    right, left, back, front = struct.unpack("<4H", ask_serial(port, batch(0x0C), 8))
    assert front > back  # microphone.h:28-31: mic3 front, mic2 back
    assert abs(right - left) < front - back


def test_light_is_brighter_towards_the_lamp(port: serial.Serial, usb: Epuck2Emulator) -> None:
    lamp = usb.world.lamp
    _face(usb, lamp.x_m, lamp.y_m)
    values = struct.unpack("<8H", ask_serial(port, batch("O"), 16))
    assert values[0] < values[3]  # lower is brighter; ps0 front-right, ps3 back-right


def test_steps_follow_the_wheels(port: serial.Serial, usb: Epuck2Emulator) -> None:
    port.write(batch("D", struct.pack("<hh", 500, -500)))
    sync(port)
    usb.world.advance(usb.world.clock() + 0.3)
    left, right = struct.unpack("<hh", ask_serial(port, batch("Q"), 4))
    truth = usb.world.step_counts()
    assert abs(left - truth[0]) <= 5 and abs(right - truth[1]) <= 5
    assert left > 100 and right < -100


def test_battery_and_sd_card_in_the_all_sensors_packet(port: serial.Serial) -> None:
    s = parse_sensors(ask_serial(port, batch(0x08), 103))
    assert s.battery == 3194  # 3.9 V, battery_level.h:14-18
    assert s.sd == 0  # no card
    assert s.tv == (0, 0, 0)
