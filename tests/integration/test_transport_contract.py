"""One contract every byte transport must pass (docs/architecture.md, "The seam").

Each transport comes with a far end that can be made to send known bytes. To add a
transport (a Bluetooth socket, say), add a factory to ``FAR_ENDS``. Channels, which
carry batches rather than bytes, have their own suite: tests/contract.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass

import pytest
from fakes import ScriptedTransport
from helpers import wait_until

from ego.errors import LinkError, LinkTimeoutError, PortNotFoundError
from ego.serial.transport import SerialTransport, Transport
from firmware_sim import Emulator


@dataclass
class FarEnd:
    """A transport, and ways to make its far end send bytes."""

    transport: Transport
    #: Make exactly four bytes arrive soon; returns them.
    send4: Callable[[], bytes]
    #: Make one ASCII line arrive soon; returns it.
    send_line: Callable[[], bytes]


@contextmanager
def loop_far_end() -> Iterator[FarEnd]:
    """pyserial's loop://: what is written comes back."""
    transport = SerialTransport("loop://")

    def send4() -> bytes:
        transport.write(b"\x01\x00\xff\x7f")
        return b"\x01\x00\xff\x7f"

    def send_line() -> bytes:
        transport.write(b"c,10\r\n")
        return b"c,10\r\n"

    try:
        yield FarEnd(transport, send4, send_line)
    finally:
        transport.close()


@contextmanager
def emulator_far_end() -> Iterator[FarEnd]:
    """The emulated dsPIC on a real pty: E answers the speeds, (0, 0) at rest."""
    with Emulator("webots", seed=1) as emu:
        transport = SerialTransport(emu.path)
        transport.drain(0.05, 2.0)  # the power-on banner

        def send4() -> bytes:
            transport.write(b"\xbb\x00")
            return bytes(4)

        def send_line() -> bytes:
            transport.write(b"C\n")
            return b"c,3\r\n"

        try:
            yield FarEnd(transport, send4, send_line)
        finally:
            transport.close()


@contextmanager
def scripted_far_end() -> Iterator[FarEnd]:
    """The test double must keep the contract too, or tests built on it prove nothing."""
    transport = ScriptedTransport()

    def send4() -> bytes:
        transport.answer(b"\x05\x06\x07\x08")
        return b"\x05\x06\x07\x08"

    def send_line() -> bytes:
        transport.answer(b"s\r\n")
        return b"s\r\n"

    yield FarEnd(transport, send4, send_line)


FAR_ENDS = {"loop": loop_far_end, "emulator-pty": emulator_far_end, "scripted": scripted_far_end}


@pytest.fixture(params=sorted(FAR_ENDS))
def far(request: pytest.FixtureRequest) -> Iterator[FarEnd]:
    with FAR_ENDS[request.param]() as far_end:
        yield far_end


def test_read_returns_once_size_arrived(far: FarEnd) -> None:
    expected = far.send4()
    start = time.monotonic()
    assert far.transport.read(4, timeout_s=10.0) == expected
    assert time.monotonic() - start < 10.0, "read waited out its timeout"


def test_read_returns_empty_on_timeout(far: FarEnd) -> None:
    assert far.transport.read(4, timeout_s=0.05) == b""


def test_read_returns_what_came_when_less_than_size(far: FarEnd) -> None:
    expected = far.send4()
    assert far.transport.read_exactly(4, 2.0) == expected
    far.send4()
    got = far.transport.read(100, timeout_s=0.1)
    assert 0 < len(got) <= 4


def test_read_exactly_returns_exactly_size_and_keeps_the_rest(far: FarEnd) -> None:
    first, second = far.send4(), far.send4()
    assert far.transport.read_exactly(6, 2.0) == (first + second)[:6]
    assert far.transport.read_exactly(2, 2.0) == (first + second)[6:]


def test_read_exactly_raises_link_timeout_with_the_partial_bytes(far: FarEnd) -> None:
    expected = far.send4()
    with pytest.raises(LinkTimeoutError, match="4 of 10") as caught:
        far.transport.read_exactly(10, 0.1)
    assert caught.value.partial == expected  # type: ignore[attr-defined]
    assert isinstance(caught.value, TimeoutError)


def test_read_exactly_of_nothing_returns_at_once(far: FarEnd) -> None:
    assert far.transport.read_exactly(0, 0.0) == b""


def test_drain_returns_what_came(far: FarEnd) -> None:
    expected = far.send4()
    assert far.transport.drain(quiet_s=0.05, max_s=2.0) == expected
    assert far.transport.drain(quiet_s=0.01, max_s=1.0) == b""


def test_pending_returns_waiting_bytes_without_blocking(far: FarEnd) -> None:
    assert far.transport.pending() == b""
    expected = far.send4()
    got = bytearray()

    def all_came() -> bool:
        got.extend(far.transport.pending())
        return len(got) >= len(expected)

    assert wait_until(all_came, interval_s=0.001), bytes(got)
    assert bytes(got) == expected


def test_read_line_returns_one_line(far: FarEnd) -> None:
    expected = far.send_line()
    assert far.transport.read_line(2.0) == expected


def test_read_line_returns_what_came_before_the_timeout(far: FarEnd) -> None:
    assert far.transport.read_line(0.05) == b""


def test_close_is_idempotent_and_the_line_is_then_gone(far: FarEnd) -> None:
    far.transport.close()
    far.transport.close()
    with pytest.raises(LinkError):
        far.transport.write(b"\x00")
    with pytest.raises(LinkError):
        far.transport.read(1, 0.0)


def test_context_manager_closes(far: FarEnd) -> None:
    with far.transport as transport:
        assert transport is far.transport
    with pytest.raises(LinkError):
        far.transport.write(b"\x00")


# -- SerialTransport only ----------------------------------------------------------------------


@pytest.mark.parametrize("url", ["/dev/does-not-exist", "bogus://nowhere", "socket://robot:42x"])
def test_port_that_cannot_be_opened_is_port_not_found(url: str) -> None:
    with pytest.raises(PortNotFoundError, match="cannot open port") as caught:
        SerialTransport(url)
    assert isinstance(caught.value, FileNotFoundError)
    assert url in str(caught.value)


def test_serial_transport_reopens_after_close() -> None:
    transport = SerialTransport("loop://")
    transport.close()
    assert not transport.is_open
    transport.reopen()
    try:
        assert transport.is_open
        transport.write(b"\x9f\x00")
        assert transport.read_exactly(2, 1.0) == b"\x9f\x00"
    finally:
        transport.close()


def test_serial_transport_names_its_port_and_rate() -> None:
    with SerialTransport("loop://", baudrate=115200) as transport:
        assert transport.name == "loop://"
        assert transport.baudrate == 115200
        assert "loop://" in repr(transport)


def test_serial_transport_defaults_to_the_overo_rate() -> None:
    """protocol.md: "On the Overo the dsPIC uses its second UART at 230400 baud"."""
    with SerialTransport("loop://") as transport:
        assert transport.baudrate == 230400
