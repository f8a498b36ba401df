"""Everything beyond the Robot follows the e-puck2 (issue 25, item 5): ``ego serve`` and the
Zenoh node serve one to a PC's controller, which reads its e-puck2 devices through them;
the supervised run stops it when its controller is killed. The e-puck2 emulator runs in
this process, on a real pty (USB, selector 8) or its radio's loopback WiFi server."""

from __future__ import annotations

import os
import signal
import socket
from collections.abc import Iterator
from contextlib import ExitStack
from pathlib import Path

import pytest
from helpers import ego_command, spawn, wait_until

import ego
from ego.serial.profiles import EPUCK2_USB, EPUCK2_WIFI
from ego.servers.zenoh_node.node import RobotNode
from ego.zenoh_net.sessions import ZenohSettings, open_session
from firmware_sim.epuck2 import Epuck2Emulator

SUPERVISED = Path(__file__).parents[1] / "reliability" / "controllers" / "supervised_controller.py"


def _free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        port: int = probe.getsockname()[1]
        return port


@pytest.fixture
def usb() -> Iterator[Epuck2Emulator]:
    with Epuck2Emulator("arena", seed=4) as emulator:
        yield emulator


@pytest.fixture
def radio() -> Iterator[Epuck2Emulator]:
    with Epuck2Emulator("arena", seed=4, wifi=True, port=0) as emulator:
        yield emulator


def _port_of(emulator: Epuck2Emulator) -> str:
    if emulator.wifi_address is not None:
        host, port = emulator.wifi_address
        return f"epuck2://{host}:{port}"
    assert emulator.pty_path is not None
    return os.path.realpath(emulator.pty_path)


def _drive_and_read(robot: ego.Robot, emulator: Epuck2Emulator) -> None:
    """A PC's controller drives the served e-puck2 and reads its own devices: the tof
    against the world's ray, the gyro turning the way the wheels turn it."""
    tof, gyro = robot.family("tof"), robot.family("gyro")
    tof.enable(64)
    gyro.enable(64)
    robot.motors.set_speed(300, -300)  # clockwise seen from above: the gyro's z < 0
    for _ in range(12):
        assert robot.step(64) == 0
    assert emulator.world.speeds == (300, -300)
    assert 0 < tof.values[0] <= 2000
    assert gyro.values[2] < -1000


@pytest.mark.parametrize("link", ["usb", "radio"])
def test_ego_serve_serves_an_e_puck2(link: str, request: pytest.FixtureRequest) -> None:
    emulator: Epuck2Emulator = request.getfixturevalue(link)
    port = _free_port()
    command = [*ego_command(), "serve", "--port", _port_of(emulator), "--camera", "none",
               "--listen", f"tcp://127.0.0.1:{port}"]  # fmt: skip
    with spawn(command, Path.cwd()) as server:
        assert server.stderr is not None
        line = server.stderr.readline()
        assert "epuck2 firmware" in line, line
        with ego.Robot(f"tcp://127.0.0.1:{port}") as robot:
            assert robot.channel.info.firmware is ego.Firmware.EPUCK2
            # The client speaks the served link's own profile (WiFi's floor has 3 values).
            assert robot.channel.profile == (EPUCK2_WIFI if link == "radio" else EPUCK2_USB)
            _drive_and_read(robot, emulator)
        assert wait_until(lambda: emulator.world.speeds == (0, 0)), "the client's close stops it"
        server.send_signal(signal.SIGTERM)
        assert server.wait(10) == 0


def test_the_zenoh_node_serves_an_e_puck2(usb: Epuck2Emulator) -> None:
    endpoint = f"tcp/127.0.0.1:{_free_port()}"
    with ExitStack() as stack:
        opened = stack.enter_context(ego.Robot(_port_of(usb)))
        served = open_session(ZenohSettings(listen=[endpoint], connect=[]))
        stack.callback(served.close)
        node = RobotNode(opened.channel, served, "e2", deadline_s=2.0).start()
        stack.callback(node.close)
        with ego.Robot("zenoh://e2", zenoh_connect=[endpoint]) as robot:
            assert robot.channel.info.firmware is ego.Firmware.EPUCK2
            _drive_and_read(robot, usb)
        assert wait_until(lambda: usb.world.speeds == (0, 0)), "the client's close stops it"


def test_a_supervised_e_puck2_is_stopped_when_its_controller_is_killed(usb: Epuck2Emulator) -> None:
    command = [*ego_command(), "run", "--supervised", "--supervisor-deadline-ms", "300",
               "--port", _port_of(usb), str(SUPERVISED), "forever"]  # fmt: skip
    with spawn(command, Path.cwd()) as run:
        assert run.stdout is not None
        line = run.stdout.readline()
        assert line.startswith("running"), (line, run.stderr.read() if run.stderr else "")
        assert wait_until(lambda: usb.world.speeds != (0, 0))
        os.kill(int(line.split()[1]), signal.SIGKILL)
        assert wait_until(lambda: usb.world.speeds == (0, 0)), "a killed controller's robot stops"
        run.wait(20)
