"""The wedge (socket_e-puck2.c:164-196): a client that leaves the radio before one valid
0x80 command leaves it reading 0 bytes for ever, never back in accept(). Whatever ego
does -- open and close a Robot, fail to open one, probe the robot -- the radio must take
the next client."""

from __future__ import annotations

import socket

import pytest
from helpers import wait_until
from wifi_relay import Relay

import ego
from ego.backends.epuck2 import probe
from ego.errors import LinkTimeoutError
from firmware_sim.epuck2 import Epuck2Emulator

ACCEPT, READ = 2, 3


def takes_a_next_client(emu: Epuck2Emulator, url: str) -> bool:
    """Whether a Robot still opens on ``emu`` (a wedged radio never answers it)."""
    try:
        with ego.Robot(url, timeout_s=1.0) as robot:
            robot.step(16)
    except LinkTimeoutError:
        return False
    return True


def test_the_check_sees_a_wedge(wifi: Epuck2Emulator, url: str) -> None:
    # The control: a bare connect-and-close does wedge the emulated radio, and the check
    # below notices it.
    assert wifi.wifi_address is not None
    socket.create_connection(wifi.wifi_address).close()
    assert wifi.radio is not None
    assert wait_until(lambda: wifi.radio.accepted == 1)  # it took that peer
    assert wifi.radio.wait_for(READ, 5.0)  # and reads it: the wedge, if any, is there
    assert not takes_a_next_client(wifi, url)


def test_opening_and_closing_a_robot_leaves_the_radio_accepting(
    wifi: Epuck2Emulator, url: str
) -> None:
    for _ in range(3):
        with ego.Robot(url) as robot:
            robot.step(16)
    assert wifi.radio is not None and wifi.radio.wait_for(ACCEPT, 5.0)
    assert takes_a_next_client(wifi, url)
    assert wifi.radio.accepted == 4


def test_a_failed_open_leaves_the_radio_accepting(
    wifi: Epuck2Emulator, url: str, relay: Relay, relay_url: str
) -> None:
    # The relay swallows the robot's replies: the open connects, hears nothing, fails.
    relay.passing = False
    with pytest.raises(LinkTimeoutError, match="selector at 15"):
        ego.Robot(relay_url, timeout_s=0.3, stop_timeout_s=0.1)
    assert relay.accepted == 1 and relay.down_bytes > 0  # it did reach the radio
    relay.cut()
    assert takes_a_next_client(wifi, url)


def test_a_probe_leaves_the_radio_accepting(wifi: Epuck2Emulator, url: str) -> None:
    assert probe(url)
    assert probe(url)
    assert takes_a_next_client(wifi, url)


def test_a_probe_of_nothing_says_so() -> None:
    with socket.socket() as free:
        free.bind(("127.0.0.1", 0))
        port = free.getsockname()[1]
    assert not probe(f"epuck2://127.0.0.1:{port}", timeout_s=0.5)
