"""The e-puck2 through ego's core on its emulator over a real pty (USB and Bluetooth): it is
detected by its ``V``, and each of its families reads what the emulated world holds and
drives what the firmware has, with every quirk of the corrections box that concerns these
links (../shared/spec/epuck2.md) pinned by a test that fails if ego gets it wrong."""

from __future__ import annotations

import math
from collections.abc import Iterator

import pytest
from helpers import IN_PROCESS_LINK

import ego
from ego.devices.sound import Melody
from ego.errors import OutOfRangeError, UnknownDeviceError, UnsupportedDeviceError
from ego.seam.profile import Firmware
from firmware_sim.epuck2 import Epuck2Emulator
from firmware_sim.world import Pose, World


def _stopped(emu: Epuck2Emulator) -> bool:
    leds = emu.robot.leds
    return (
        emu.world.speeds == (0, 0)
        and not any(leds.red)
        and not leds.body
        and not leds.front
        and all(channel == 0 for rgb in leds.rgb for channel in rgb)
    )


@pytest.fixture(params=[False, True], ids=["usb", "bluetooth"])
def emu(request: pytest.FixtureRequest) -> Iterator[Epuck2Emulator]:
    """An e-puck2 in a quiet world, 10 cm from the east wall, facing it."""
    world = World(seed=3, noise=False)
    with Epuck2Emulator(world, seed=3, bluetooth=request.param) as emulator:
        yield emulator


@pytest.fixture
def usb() -> Iterator[Epuck2Emulator]:
    with Epuck2Emulator(World(seed=3, noise=False), seed=3) as emulator:
        yield emulator


def _open(emulator: Epuck2Emulator) -> ego.Robot:
    assert emulator.pty_path is not None
    baud = 115200 if emulator.firmware.use_bt else 230400
    return ego.Robot(emulator.pty_path, baudrate=baud, link_settings=IN_PROCESS_LINK)


@pytest.fixture
def robot(emu: Epuck2Emulator) -> Iterator[ego.Robot]:
    with _open(emu) as opened:
        yield opened
    assert _stopped(emu), "the robot was left running or lit"


@pytest.fixture
def usb_robot(usb: Epuck2Emulator) -> Iterator[ego.Robot]:
    with _open(usb) as opened:
        yield opened
    assert _stopped(usb), "the robot was left running or lit"


def test_the_port_opens_as_an_e_puck2(robot: ego.Robot, emu: Epuck2Emulator) -> None:
    info = robot.channel.info
    assert info.firmware is Firmware.EPUCK2
    assert info.selector == (3 if emu.firmware.use_bt else 8)
    assert info.profile.line_baud == (115200 if emu.firmware.use_bt else 10_000_000)


def test_the_new_families_read_the_world(robot: ego.Robot, emu: Epuck2Emulator) -> None:
    for family in (robot.tof, robot.gyro, robot.temperature, robot.selector, robot.button,
                   robot.microphones, robot.battery, robot.proximity):  # fmt: skip
        family.enable(32)
    emu.robot.button = True
    robot.step(32)
    truth = emu.robot.tof.distance_mm()
    assert robot.tof.distance_mm == truth and 0 < truth < 2000
    assert robot.temperature.celsius == 30  # the emulator's constant
    assert robot.selector.position == (3 if emu.firmware.use_bt else 8)
    assert robot.button.pressed
    assert len(robot.microphones.values) == 4 and robot.microphones.member_names[-1] == "mic3"
    assert robot.battery.raw == emu.robot.battery.raw()


def test_the_gyro_sees_the_robot_turn_counter_clockwise(robot: ego.Robot) -> None:
    robot.gyro.enable(32)
    robot.motors.set_speed(-300, 300)  # left back, right forward: counter-clockwise
    for _ in range(5):
        robot.step(32)
    x, y, z = robot.gyro.values
    assert z > 1000 and abs(x) < 50 and abs(y) < 50
    assert robot.gyro.rates_rad_s[2] == pytest.approx(z / 131.072 * math.pi / 180)
    robot.motors.set_speed(0, 0)


def test_the_magnetometer_is_switched_on_before_it_is_read(robot: ego.Robot) -> None:
    # Over USB and Bluetooth the firmware leaves it off, reading 0.0, until -0x0F 1.
    robot.magnetometer.enable(32)
    robot.step(32)
    x, y, z = robot.magnetometer.values
    assert math.hypot(x, y, z) > 20  # the Earth's field, about 48 uT


def test_the_accelerometer_reads_one_g_down_from_the_0_centred_packet(
    robot: ego.Robot,
) -> None:
    # Corrections box: the packet's accelerometer is centred on 0 (about 768 a g).
    robot.accelerometer.enable(32)
    robot.step(32)
    x, y, z = robot.accelerometer.acceleration_mps2
    assert z == pytest.approx(9.81, abs=0.6) and abs(x) < 0.6 and abs(y) < 0.6


def test_negative_speeds_drive_backwards(usb_robot: ego.Robot, usb: Epuck2Emulator) -> None:
    # Corrections box: the sign of negative speeds (-'D' stores them unsigned, cast to int16).
    start = usb.world.snapshot()
    usb_robot.motors.set_speed(-400, -400)
    usb_robot.motors.enable(32)
    for _ in range(10):
        usb_robot.step(32)
    assert usb.world.speeds == (-400, -400)
    assert usb_robot.motors.values == (-400, -400)  # binary E echoes them signed
    moved = usb.world.snapshot()
    heading = (math.cos(start.theta_rad), math.sin(start.theta_rad))
    assert (moved.x_m - start.x_m) * heading[0] + (moved.y_m - start.y_m) * heading[1] < -0.005
    assert usb_robot.channel.stats.faults["implausible"] == 0
    usb_robot.motors.set_speed(0, 0)


def test_the_speed_limit_is_1100_steps_s(usb_robot: ego.Robot, usb: Epuck2Emulator) -> None:
    usb_robot.motors.set_speed(1100, -1100)
    usb_robot.step(32)
    assert usb.world.speeds == (1100, -1100)
    with pytest.raises(OutOfRangeError, match=r"1101 steps/s is outside -1100\.\.1100"):
        usb_robot.motors.set_speed(1101, 0)
    usb_robot.motors.set_speed(0, 0)


def test_rgb_leds_go_as_percent_in_red_green_blue(
    usb_robot: ego.Robot, usb: Epuck2Emulator
) -> None:
    # Corrections box, the LED bytes: R, G, B in 0..100 % (Webots' builder sends B, G, R
    # in 0..255), and an -'L' on an odd LED would set the red channel alone at 10 %.
    usb_robot.leds.set("led1", 0xFF8000)
    usb_robot.leds.set("led3", 0x0000FF)
    usb_robot.leds.set("led0", 1)
    usb_robot.leds.set("led8", 1)
    usb_robot.step(32)
    leds = usb.robot.leds
    assert leds.rgb[0] == [100, 50, 0] and leds.rgb[1] == [0, 0, 100]
    assert leds.rgb[2] == leds.rgb[3] == [0, 0, 0]
    assert leds.red == [True, False, False, False]
    assert leds.body and not leds.front  # binary L 8 is the body alone (ASCII L,8: the ring)
    assert usb_robot.leds.get("led1") == 0xFF8000
    with pytest.raises(OutOfRangeError, match="colour for led1"):
        usb_robot.leds.set("led1", 0x1000000)


def test_ascii_s_stops_and_ego_resends_the_echoed_speeds(
    usb_robot: ego.Robot, usb: Epuck2Emulator
) -> None:
    # Corrections box: S leaves the body and front LEDs and the speeds E reports.
    usb_robot.motors.set_speed(300, 300)
    usb_robot.leds.set("led8", 1)
    usb_robot.leds.set("led5", 0x00FF00)
    usb_robot.step(32)
    usb_robot.ascii_command("S")
    assert usb.world.speeds == (0, 0) and usb.robot.leds.rgb[2] == [0, 0, 0]
    assert usb_robot.leds.get("led5") == 0 and usb_robot.leds.get("led8") == 1
    usb_robot.step(32)  # the D 0 0 ego queued makes E echo the truth again
    assert usb.firmware.state.speedl == 0 and usb_robot.channel.stats.faults["implausible"] == 0


def test_an_ascii_command_leaves_the_next_batch_whole(usb_robot: ego.Robot) -> None:
    # Corrections box: a \n after a \r-terminated line swallows the next byte, even a
    # binary one; ego ends its lines with \n alone, so the next batch is answered at once.
    usb_robot.proximity.enable(32)
    for _ in range(3):
        assert usb_robot.ascii_command("V")[0].startswith("v,Version 2.0")
        usb_robot.step(32)
    stats = usb_robot.channel.stats
    assert stats.resyncs == 0 and stats.retries == 0


def test_the_speaker_plays_each_sound_once(usb_robot: ego.Robot, usb: Epuck2Emulator) -> None:
    usb_robot.sound.play(Melody.STAR_WARS)
    usb_robot.step(32)
    usb_robot.step(32)
    usb_robot.sound.stop()
    names = usb.robot.sound_names()
    assert names.count(names[0]) == 1 and names[-1] == "stop" and len(names) == 2
    with pytest.raises(OutOfRangeError, match="sound 9 is not one of"):
        usb_robot.sound.play(9)


def test_the_mic_buffer_is_refused_at_once(usb_robot: ego.Robot) -> None:
    with pytest.raises(UnsupportedDeviceError, match="'U'"):
        usb_robot.microphones.enable_buffer(100)


def test_the_e_puck2_families_are_absent_on_an_e_puck() -> None:
    with ego.Robot("sim", seed=1) as robot:
        for family in (robot.tof, robot.gyro, robot.magnetometer, robot.temperature,
                       robot.button, robot.selector):  # fmt: skip
            assert family.member_names == ()
            with pytest.raises(UnsupportedDeviceError):
                family.enable(32)  # type: ignore[attr-defined]
        with pytest.raises(UnknownDeviceError):
            robot.device("tof")
        with pytest.raises(UnsupportedDeviceError, match="no speaker"):
            robot.sound.play(Melody.MARIO)


def test_sim_opens_an_e_puck2_and_drives_it() -> None:
    with ego.Robot("sim", robot="epuck2", seed=2, world="arena") as robot:
        assert robot.channel.profile.firmware is Firmware.EPUCK2
        robot.tof.enable(32)
        robot.motors.set_speed(200, 200)
        robot.step(32)
        truth = robot.ground_truth
        assert truth is not None and robot.tof.has_values
    with pytest.raises(OutOfRangeError, match="robot 'epuck3' is not one of epuck, epuck2"):
        ego.Robot("sim", robot="epuck3")


def test_the_tof_faces_what_the_world_puts_in_front() -> None:
    world = World(seed=5, noise=False)
    world.start_at(Pose(0.0, 0.0, 0.0))
    with Epuck2Emulator(world, seed=5) as emulator, _open(emulator) as robot:
        robot.tof.enable(32)
        robot.step(32)
        far = robot.tof.distance_mm
        robot.motors.set_speed(800, 800)
        for _ in range(30):
            robot.step(32)
        robot.motors.set_speed(0, 0)
        robot.step(100)
        near = robot.tof.distance_mm
        assert near < far - 50
