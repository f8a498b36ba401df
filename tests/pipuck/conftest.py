"""Fixtures: an emulated Pi-puck (firmware_sim.pipuck) and ways to run ego against it in
a child process, where the LD_PRELOAD shim turns ``/dev/i2c-N`` into the emulator: ego's
real smbus2 ioctls, never a Python stand-in."""

from __future__ import annotations

import threading
from collections.abc import Callable, Iterator
from typing import Any

import pytest
from pipuck_support import Runner

from firmware_sim.pipuck import PipuckEmulator
from firmware_sim.world import World

THREAD = "ego-sim-pipuck"


@pytest.fixture(autouse=True)
def no_leaked_pipuck() -> Iterator[None]:
    before = {t for t in threading.enumerate() if t.name == THREAD}
    yield
    after = {t for t in threading.enumerate() if t.name == THREAD and t.is_alive()}
    assert not after - before, "the Pi-puck emulator's socket thread outlived its test"


def open_world() -> World:
    """An arena with nothing near the robot's start (the world's default start)."""
    return World(seed=1)


@pytest.fixture
def pipuck() -> Iterator[Callable[..., PipuckEmulator]]:
    """``pipuck(robot="epuck2", buses="current", **options)``: an emulator, closed after."""
    made: list[PipuckEmulator] = []

    def make(robot: str = "epuck2", buses: str = "current", **options: Any) -> PipuckEmulator:
        options.setdefault("seed", 1)
        made.append(PipuckEmulator(robot, buses, **options).__enter__())
        return made[-1]

    yield make
    for emu in made:
        emu.__exit__(None, None, None)


@pytest.fixture
def runner(tmp_path: Any) -> Iterator[Callable[[PipuckEmulator], Runner]]:
    """``runner(emu)``: runs ``ego`` commands and scripts in ``emu``'s environment."""
    runners: list[Runner] = []

    def make(emu: PipuckEmulator) -> Runner:
        runners.append(Runner(emu, tmp_path))
        return runners[-1]

    yield make
    for made in runners:
        made.close()
