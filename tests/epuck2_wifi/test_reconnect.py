"""A WiFi drop: the robot keeps its last speeds until a new command comes, so ego
reconnects within the link's deadline with the controller's current command (the stop
when the controller has gone), or fails with a LinkLostError naming the robot and why.
And a robot that cannot be reached gives a clear error at once."""

from __future__ import annotations

import socket
import time

import pytest
from helpers import wait_until
from wifi_relay import Relay

import ego
from ego.core.registry import open_port
from ego.errors import LinkLostError, LinkTimeoutError, PortNotFoundError
from firmware_sim.epuck2 import Epuck2Emulator

#: socket_task's state while it waits for a client (it saw the last one go).
ACCEPT = 2


def test_after_a_drop_the_wheels_follow_the_controller(
    wifi: Epuck2Emulator, relay: Relay, relay_url: str
) -> None:
    with ego.Robot(relay_url) as robot:
        robot.motors.set_speed(300, 300)
        robot.step(16)
        assert wait_until(lambda: wifi.world.speeds == (300, 300))
        assert relay.cut() == 1
        assert wifi.radio is not None and wifi.radio.wait_for(ACCEPT, 5.0)  # it saw the cut
        assert wifi.world.speeds == (300, 300)  # the robot keeps its last speeds
        robot.motors.set_speed(-200, 150)
        robot.step(16)
        assert wait_until(lambda: wifi.world.speeds == (-200, 150))
        assert robot.channel.stats.reconnects == 1
        assert relay.accepted == 2


def test_a_drop_while_the_controller_reads_reconnects_too(
    wifi: Epuck2Emulator, relay: Relay, relay_url: str
) -> None:
    with ego.Robot(relay_url) as robot:
        robot.proximity.enable(16)
        robot.motors.set_speed(250, -250)
        robot.step(16)
        relay.cut()
        for _ in range(5):
            robot.step(16)  # the step's answers wait on the new connection
        assert wait_until(lambda: wifi.world.speeds == (250, -250))
        assert robot.channel.stats.reconnects == 1


def test_a_drop_then_the_controller_gone_stops_the_robot(
    wifi: Epuck2Emulator, relay: Relay, relay_url: str
) -> None:
    robot = ego.Robot(relay_url)
    robot.motors.set_speed(350, 350)
    robot.step(16)
    assert wait_until(lambda: wifi.world.speeds == (350, 350))
    relay.cut()
    assert wifi.radio is not None and wifi.radio.wait_for(ACCEPT, 5.0)  # it saw the cut
    assert wifi.world.speeds == (350, 350)  # the robot keeps its last speeds
    robot.close()  # the close reconnects with the stop as its first command
    assert wait_until(lambda: wifi.world.speeds == (0, 0))


def test_a_robot_that_does_not_come_back_is_a_clear_link_lost_error(
    relay: Relay, relay_url: str, caplog: pytest.LogCaptureFixture
) -> None:
    from ego.backends.epuck2.requests import WIFI_PROFILE
    from ego.seam.batch import Request
    from ego.seam.profile import Command
    from ego.serial.protocol import encode_batch

    opened = open_port(relay_url, reconnect_s=0.3, timeout_s=0.3, stop_timeout_s=0.1)
    try:
        relay.accepting = False
        relay.cut()
        assert wait_until(lambda: opened.channel.heard.lost is not None)  # the reader saw it
        batch = encode_batch([Request(Command.SET_SPEED, (100, 100))], WIFI_PROFILE)
        with pytest.raises(LinkLostError, match=rf"{relay_url}: lost, and not back within 0.3 s"):
            opened.channel.exchange(batch)
    finally:
        opened.close()


def test_a_robot_step_after_the_link_is_lost_says_so(
    relay: Relay, relay_url: str, caplog: pytest.LogCaptureFixture
) -> None:
    robot = ego.Robot(relay_url, reconnect_s=0.3, timeout_s=0.3, stop_timeout_s=0.1)
    try:
        assert robot.step(16) == 0
        relay.accepting = False
        relay.cut()
        assert wait_until(lambda: robot.channel.heard.lost is not None)  # the reader saw it
        robot.motors.set_speed(100, 100)
        assert robot.step(16) == -1  # Webots' step: the link is gone
    finally:
        robot.close()
    assert any(relay_url in r.getMessage() and "not back within 0.3 s" in r.getMessage()
               for r in caplog.records)  # fmt: skip


def test_a_closed_port_is_refused_at_once() -> None:
    with socket.socket() as free:
        free.bind(("127.0.0.1", 0))
        port = free.getsockname()[1]
    url = f"epuck2://127.0.0.1:{port}"
    with pytest.raises(PortNotFoundError, match=rf"{url}: connection refused"):
        ego.Robot(url)


def test_an_address_that_never_answers_times_out() -> None:
    # A listening socket that never accepts: the handshake completes in its backlog,
    # the command goes out, and nothing ever comes back.
    with socket.socket() as deaf:
        deaf.bind(("127.0.0.1", 0))
        deaf.listen(1)
        url = f"epuck2://127.0.0.1:{deaf.getsockname()[1]}"
        start = time.monotonic()
        with pytest.raises(LinkTimeoutError, match=rf"{url}: .*no reply within 0.5 s"):
            ego.Robot(url, timeout_s=0.5)
        assert time.monotonic() - start < 5.0  # a generous budget: it does not hang


def test_a_name_is_resolved_once(wifi: Epuck2Emulator) -> None:
    assert wifi.wifi_address is not None
    url = f"epuck2://localhost:{wifi.wifi_address[1]}"
    opened = open_port(url)
    try:
        assert opened.channel.name == url
        assert opened.channel.address == ("127.0.0.1", wifi.wifi_address[1])  # type: ignore[attr-defined]
    finally:
        opened.close()


def test_a_malformed_port_is_named() -> None:
    with pytest.raises(PortNotFoundError, match="is not epuck2://HOST"):
        ego.Robot("epuck2://robot:1000/some/path")
