"""The lost stop (socket_e-puck2.c:199-276): the radio sends before it reads, and a send
error sends it back to accept() without handing on the command it read, so a stop sent
just before hanging up is lost (tests/emulator_epuck2/test_wifi_traps.py shows it). A
Robot's close must see its stop answered; if the answer never comes, it says so."""

from __future__ import annotations

import logging
import time

import pytest
from helpers import wait_until
from wifi_relay import Relay

import ego
from firmware_sim.epuck2 import Epuck2Emulator

ACCEPT = 2


@pytest.mark.parametrize("camera", [False, True], ids=["sensors", "images"])
def test_closing_a_robot_stops_it_whatever_the_radio_s_phase(
    wifi: Epuck2Emulator, url: str, camera: bool
) -> None:
    # With the camera on, 38 KB frames are in flight when the robot closes: hanging up
    # on them resets the connection, the radio's next send fails, and a stop it read
    # but had not yet handed on is lost, unless ego waited for the stop's answer.
    assert wifi.radio is not None
    for trial in range(6):
        robot = ego.Robot(url)
        robot.motors.set_speed(400 + trial, 400 + trial)
        if camera:
            robot.camera.enable(16)
        robot.step(16)
        speeds = (400 + trial, 400 + trial)
        assert wait_until(lambda speeds=speeds: wifi.world.speeds == speeds)
        robot.close()
        assert wifi.radio.wait_for(ACCEPT, 5.0)
        assert wifi.world.speeds == (0, 0), f"trial {trial}: the stop was lost"
        time.sleep(0.007 * trial)  # meet the radio's 10 ms loop at another phase


def test_closing_the_channel_alone_sees_its_stop_answered(wifi: Epuck2Emulator, url: str) -> None:
    # Without the Robot's own stop batch: the channel's close sends the stop itself.
    from ego.backends.epuck2.requests import WIFI_PROFILE
    from ego.core.registry import open_port
    from ego.seam.batch import Request
    from ego.seam.profile import Command
    from ego.serial.protocol import encode_batch

    opened = open_port(url)
    opened.channel.exchange(encode_batch([Request(Command.SET_SPEED, (-300, 250))], WIFI_PROFILE))
    assert wait_until(lambda: wifi.world.speeds == (-300, 250))
    opened.close()
    assert wifi.radio is not None and wifi.radio.wait_for(ACCEPT, 5.0)
    assert wifi.world.speeds == (0, 0)


def test_a_stop_never_answered_is_logged(
    relay: Relay, relay_url: str, caplog: pytest.LogCaptureFixture
) -> None:
    robot = ego.Robot(relay_url, stop_timeout_s=0.3, timeout_s=0.3, reconnect_s=0.3)
    robot.step(16)
    relay.passing = False  # the robot's answers no longer arrive
    with caplog.at_level(logging.ERROR):
        robot.close()
    assert any("stop" in r.getMessage() and relay_url in r.getMessage() for r in caplog.records)
