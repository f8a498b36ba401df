"""Issue 32, item 9: the Overo's I2C reader has a timeout of its own, and a short or
garbled chip reply is a typed error. Before, a transfer that hung held the step for as
long as the kernel did (the OMAP3's driver waits 1 s a message), and a reply of the wrong
length escaped as ``struct.error``. Now each transfer runs on the bus's worker thread and
the step waits until its own deadline and goes on without the reading, never for the
transfer's end (a loaded board is late, not broken); once the transfer has held the bus
for HUNG_S (1 s, the OMAP3's own limit) it has hung: the family is disabled, naming it
(UnsupportedDeviceError).
A short or long reply, read again, is a ShortReplyError or ExtraBytesError.

The bus doubles wrap the emulator's model of the bus and are passed in (``i2c=``)."""

from __future__ import annotations

import threading
import time

import pytest
from helpers import wait_until

import ego
from ego.errors import ExtraBytesError, ShortReplyError, UnsupportedDeviceError
from ego.i2c.side import MAX_I2C_ATTEMPTS
from ego.i2c.worker import HUNG_S
from firmware_sim import Emulator
from firmware_sim.i2c import OveroBus

STEP_MS = 32
#: How long the test lets the bus hang before it gives up on the family being disabled.
HANG_S = 3.0
#: How long the hanging double holds a transfer at most, if the test never releases it.
HOLD_MAX_S = 30.0


class HangingBus:
    """The emulator's bus, whose reads hang once ``hang`` is set until ``release``;
    ``hung_reads_ended`` counts the hung reads that have returned."""

    def __init__(self, inner: OveroBus) -> None:
        self.inner, self.name = inner, inner.name
        self.hang = threading.Event()
        self.release = threading.Event()
        self.hung_reads_ended = 0
        self.reads_after_release = 0

    def read_block(self, address: int, register: int, count: int) -> bytes:
        if self.hang.is_set():
            try:
                self.release.wait(HOLD_MAX_S)
            finally:
                self.hung_reads_ended += 1
        elif self.release.is_set():
            self.reads_after_release += 1
        return self.inner.read_block(address, register, count)

    def write_byte_data(self, address: int, register: int, value: int) -> None:
        self.inner.write_byte_data(address, register, value)

    def close(self) -> None:
        self.inner.close()


class MisshapenBus:
    """The emulator's bus, whose next ``garble`` reads answer ``change`` bytes more (or
    fewer) than asked (a garbled or cut reply); ``armed`` garbles every read."""

    def __init__(self, inner: OveroBus, change: int) -> None:
        self.inner, self.name, self.change = inner, inner.name, change
        self.armed = False
        self.garble = 0

    def read_block(self, address: int, register: int, count: int) -> bytes:
        data = self.inner.read_block(address, register, count)
        if self.garble > 0:
            self.garble -= 1
        elif not self.armed:
            return data
        return data[: count + self.change] if self.change < 0 else data + b"\xff" * self.change

    def write_byte_data(self, address: int, register: int, value: int) -> None:
        self.inner.write_byte_data(address, register, value)

    def close(self) -> None:
        self.inner.close()


def test_a_hung_bus_never_holds_a_step_and_disables_its_family(
    overo_emulator: Emulator,
) -> None:
    assert overo_emulator.i2c is not None
    bus = HangingBus(overo_emulator.i2c)
    with ego.Robot(overo_emulator.path, i2c=bus) as robot:
        try:
            robot.floor.enable(STEP_MS)
            assert robot.step(STEP_MS) == 0 and robot.floor.has_values
            before = robot.floor.values
            bus.hang.set()
            hung_at = time.monotonic()
            with pytest.raises(UnsupportedDeviceError, match=r"held .* does not end"):
                # Each step goes on without the late reading, by its own deadline: it
                # returns before the transfer has ended, until the transfer has
                # held it for HUNG_S: then it has hung.
                while time.monotonic() - hung_at < HANG_S:
                    start = time.monotonic()
                    try:
                        assert robot.step(STEP_MS) == 0
                        assert robot.floor.values == before  # the last reading, kept
                    finally:
                        took = time.monotonic() - start
                    assert bus.hung_reads_ended == 0, f"the step waited for it ({took:.2f} s)"
                    assert took < HUNG_S, f"a step took {took:.2f} s"
            assert time.monotonic() - hung_at >= HUNG_S  # never before the bus has hung
            assert not robot.floor.enabled
        finally:
            bus.release.set()  # the kernel ends the transfer; close joins the worker


def test_a_late_reading_is_taken_at_a_later_step(overo_emulator: Emulator) -> None:
    """A transfer past the step's deadline (a loaded board) is no fault: the family stays
    enabled and its next reading arrives once the bus is free."""
    assert overo_emulator.i2c is not None
    bus = HangingBus(overo_emulator.i2c)
    with ego.Robot(overo_emulator.path, i2c=bus) as robot:
        robot.floor.enable(STEP_MS)
        assert robot.step(STEP_MS) == 0
        bus.hang.set()
        assert robot.step(STEP_MS) == 0  # the read outlives its step
        bus.hang.clear()
        bus.release.set()
        assert robot.step(STEP_MS) == 0 and robot.floor.enabled
        assert wait_until(lambda: robot.step(STEP_MS) == 0 and bus.reads_after_release > 0)
        assert robot.floor.enabled and robot.floor.has_values


@pytest.mark.parametrize(("change", "error"), [(-1, ShortReplyError), (2, ExtraBytesError)])
def test_a_short_or_long_chip_reply_is_a_typed_error(
    overo_emulator: Emulator, change: int, error: type[Exception]
) -> None:
    assert overo_emulator.i2c is not None
    bus = MisshapenBus(overo_emulator.i2c, change)
    with ego.Robot(overo_emulator.path, i2c=bus) as robot:
        robot.floor.enable(STEP_MS)
        assert robot.step(STEP_MS) == 0
        bus.garble = MAX_I2C_ATTEMPTS  # the read and each reading again
        with pytest.raises(error, match="reading the ground module at 0x60"):
            # On a loaded machine the read may outlive its step: the error comes with the
            # step that takes the reading (test_a_late_reading_is_taken_at_a_later_step).
            for _ in range(50):
                robot.step(STEP_MS)
        assert robot.step(STEP_MS) == 0 and robot.floor.enabled  # read again next step


def test_a_short_reply_to_the_probe_is_a_chip_not_found(overo_emulator: Emulator) -> None:
    assert overo_emulator.i2c is not None
    bus = MisshapenBus(overo_emulator.i2c, -1)
    bus.armed = True
    with (
        ego.Robot(overo_emulator.path, i2c=bus) as robot,
        pytest.raises(UnsupportedDeviceError, match="0x60: 5 bytes, not 6"),
    ):
        robot.floor.enable(STEP_MS)
