"""Fixtures: the emulated e-puck2 on a real pty (USB, Bluetooth) or a real loopback TCP
port (WiFi), and a check that none of its threads outlive a test."""

from __future__ import annotations

import os
import threading
from collections.abc import Iterator

import pytest
import serial
from epuck2_wire import WifiClient, read_quiet

from firmware_sim.epuck2 import Epuck2Emulator
from firmware_sim.world import World

THREADS = ("epuck2-serial", "epuck2-radio")


def _threads() -> set[threading.Thread]:
    return {t for t in threading.enumerate() if t.name in THREADS and t.is_alive()}


@pytest.fixture(autouse=True)
def no_leaked_epuck2() -> Iterator[None]:
    threads = _threads()
    yield
    assert not _threads() - threads, "e-puck2 emulator threads left running"


@pytest.fixture
def usb() -> Iterator[Epuck2Emulator]:
    """An e-puck2 in selector 8 (asercom v2 over USB) in a quiet world."""
    with Epuck2Emulator(World(seed=1, noise=False), seed=1) as emu:
        yield emu
    assert emu.pty_path is not None
    assert not os.path.exists(os.path.dirname(emu.pty_path)), "its pty directory stayed"


@pytest.fixture
def port(usb: Epuck2Emulator) -> Iterator[serial.Serial]:
    assert usb.pty_path is not None
    with serial.Serial(usb.pty_path, 115200, timeout=0.2) as port:
        read_quiet(port, 0.05)
        yield port


@pytest.fixture
def wifi() -> Iterator[Epuck2Emulator]:
    """An e-puck2 in selector 15, its radio on an ephemeral loopback port."""
    with Epuck2Emulator(World(seed=2, noise=False), seed=2, wifi=True, port=0) as emu:
        yield emu


@pytest.fixture
def client(wifi: Epuck2Emulator) -> Iterator[WifiClient]:
    assert wifi.wifi_address is not None
    c = WifiClient(wifi.wifi_address)
    yield c
    c.close()
