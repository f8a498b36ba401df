"""Where to connect: the argument, else EGO_PORT, else /dev/ttyS0 (api.md)."""

from __future__ import annotations

import pytest

from ego.backends import open_port, scheme_of
from ego.errors import PortNotFoundError
from ego.ports import DEFAULT_PORT, resolve_port
from ego.serial.transport import SerialTransport


def test_explicit_port_wins(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("EGO_PORT", "/dev/ttyUSB0")
    assert resolve_port("loop://") == "loop://"


def test_environment_names_the_port_when_none_is_given(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("EGO_PORT", "/dev/ttyUSB0")
    assert resolve_port(None) == "/dev/ttyUSB0"


def test_overo_uart_is_the_default(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv("EGO_PORT", raising=False)
    assert resolve_port(None) == DEFAULT_PORT == "/dev/ttyS0"


def test_pyserial_urls_open_a_serial_transport() -> None:
    opened = open_port("loop://", baudrate=115200)
    with opened.transport as transport:
        assert isinstance(transport, SerialTransport)
        assert transport.baudrate == 115200


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
    from ego.backends import find_backend

    with pytest.raises(PortNotFoundError, match="no backend serves 'zenoh'"):
        find_backend("zenoh")
