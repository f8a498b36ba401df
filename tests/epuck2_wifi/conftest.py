"""Fixtures: the emulated e-puck2's real WiFi server on a loopback port, a relay in front
of it, and a check that no emulator, channel or relay thread outlives a test."""

from __future__ import annotations

import threading
from collections.abc import Iterator

import pytest
from wifi_relay import Relay

from firmware_sim.epuck2 import Epuck2Emulator
from firmware_sim.world import World

THREADS = ("epuck2-radio", "epuck2-wifi-reader", "epuck2-test-relay")


def _threads() -> set[threading.Thread]:
    return {t for t in threading.enumerate() if t.name in THREADS and t.is_alive()}


@pytest.fixture(autouse=True)
def no_leaked_threads() -> Iterator[None]:
    before = _threads()
    yield
    assert not _threads() - before, "a WiFi thread was left running"


@pytest.fixture
def wifi() -> Iterator[Epuck2Emulator]:
    """An e-puck2 in selector 15 in a quiet world, its radio on an ephemeral port."""
    with Epuck2Emulator(World(seed=2, noise=False), seed=2, wifi=True, port=0) as emu:
        yield emu


@pytest.fixture
def url(wifi: Epuck2Emulator) -> str:
    assert wifi.wifi_address is not None
    host, port = wifi.wifi_address
    return f"epuck2://{host}:{port}"


@pytest.fixture
def relay(wifi: Epuck2Emulator) -> Iterator[Relay]:
    assert wifi.wifi_address is not None
    r = Relay(wifi.wifi_address)
    yield r
    r.close()


@pytest.fixture
def relay_url(relay: Relay) -> str:
    host, port = relay.address
    return f"epuck2://{host}:{port}"
