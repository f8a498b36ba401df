"""Fixtures: an emulated Pi-puck in a quiet world on virtual time, and a client process
that reaches it through the LD_PRELOAD shim with the real smbus2."""

from __future__ import annotations

import threading
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from pipuck_harness import Client, quiet_world

from firmware_sim.pipuck import PipuckEmulator

THREAD = "ego-sim-pipuck"


@pytest.fixture(autouse=True)
def no_leaked_pipuck() -> Iterator[None]:
    before = {t for t in threading.enumerate() if t.name == THREAD}
    yield
    after = {t for t in threading.enumerate() if t.name == THREAD and t.is_alive()}
    assert not after - before, "the Pi-puck emulator's socket thread outlived its test"


@pytest.fixture
def epuck2() -> Iterator[PipuckEmulator]:
    with PipuckEmulator("epuck2", "current", quiet_world(), seed=1, virtual_time=True) as emu:
        yield emu
    assert not Path(emu.socket_path).exists(), "the emulator's socket stayed"


@pytest.fixture
def epuck1() -> Iterator[PipuckEmulator]:
    with PipuckEmulator("epuck", "current", quiet_world(), seed=1, virtual_time=True) as emu:
        yield emu


@pytest.fixture
def client_of() -> Iterator[Any]:
    """``client_of(emu)``: a client process in ``emu``'s environment, ended after."""
    clients: list[Client] = []

    def start(emu: PipuckEmulator) -> Client:
        clients.append(Client(emu.environ()))
        return clients[-1]

    yield start
    for client in clients:
        client.close()
