"""Where to connect: the argument, else EGO_PORT, else /dev/ttyS0 (README, "Use")."""

from __future__ import annotations

import pytest

import ego
from ego.core.environment import read_environment
from ego.core.ports import DEFAULT_PORT, resolve_port
from ego.core.registry import open_port, scheme_of
from ego.errors import NotAnEpuckError, PortNotFoundError
from ego.seam.profile import Firmware
from ego.serial.link import Link
from ego.serial.transport import SerialTransport
from firmware_sim import Emulator

#: What ``EGO_PORT=/dev/ttyUSB0`` in the environment reads as (ego.core.environment).
USB = read_environment({"EGO_PORT": "/dev/ttyUSB0"})


def test_explicit_port_wins() -> None:
    assert resolve_port("loop://", USB.port) == "loop://"


def test_environment_names_the_port_when_none_is_given() -> None:
    assert resolve_port(None, USB.port) == "/dev/ttyUSB0"


def test_overo_uart_is_the_default() -> None:
    assert resolve_port(None, read_environment({}).port) == DEFAULT_PORT == "/dev/ttyS0"


def test_a_robot_opened_without_a_port_opens_the_environments() -> None:
    # The Robot is the edge: it reads the environment it is given (else the process's).
    with pytest.raises(PortNotFoundError, match="/dev/ego-no-such-port"):
        ego.Robot(environment=read_environment({"EGO_PORT": "/dev/ego-no-such-port"}))


def test_a_path_opens_a_link_on_a_serial_transport_at_the_asked_rate() -> None:
    with Emulator("webots", seed=1) as emu:
        opened = open_port(emu.path, baudrate=115200)
        try:
            assert isinstance(opened.channel, Link)
            assert isinstance(opened.channel.transport, SerialTransport)
            assert opened.channel.transport.baudrate == 115200
            assert opened.channel.info.firmware is Firmware.WEBOTS
        finally:
            opened.close()


def test_a_pyserial_url_that_is_no_robot_is_closed_again() -> None:
    # loop:// echoes every byte: an answer, but not a dsPIC's.
    with pytest.raises(NotAnEpuckError):
        open_port("loop://", baudrate=115200)


def test_an_option_the_backend_does_not_know_is_refused() -> None:
    with pytest.raises(ValueError, match="seed"):
        open_port("loop://", seed=3)


def test_missing_port_is_port_not_found() -> None:
    with pytest.raises(PortNotFoundError, match="/dev/does-not-exist"):
        open_port("/dev/does-not-exist")


@pytest.mark.parametrize(
    ("port", "scheme"),
    [("/dev/ttyS0", "serial"), ("socket://h:1", "serial"), ("loop://", "serial"),
     ("tcp://robot:4242", "tcp"), ("udp://robot:4242", "udp"), ("sim", "sim")],
)  # fmt: skip
def test_each_port_goes_to_the_backend_of_its_scheme(port: str, scheme: str) -> None:
    assert scheme_of(port) == scheme


def test_an_unknown_backend_says_what_is_missing() -> None:
    from ego.core.registry import find_backend

    with pytest.raises(PortNotFoundError, match="no backend serves 'carrier-pigeon'"):
        find_backend("carrier-pigeon")
