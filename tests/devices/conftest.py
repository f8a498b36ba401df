"""Fixtures for the device, scheduler and Robot tests: the emulated dsPIC on a real pty, and
robots on it that must have stopped their motors and switched their LEDs off by the end."""

from __future__ import annotations

from collections.abc import Iterator

import pytest
from helpers import IN_PROCESS_LINK, assert_stopped

import ego
from firmware_sim import Emulator
from tests.helpers import world_of

#: One seed for every emulator here, so that a failure replays with the same sensor noise.
SEED = 7


@pytest.fixture
def emulator() -> Iterator[Emulator]:
    """The thesis firmware's dsPIC behind a pty, outliving the robot so the stop is seen."""
    with Emulator("webots", seed=SEED) as emu:
        yield emu


@pytest.fixture
def sim_robot(emulator: Emulator) -> Iterator[ego.Robot]:
    """A robot on the emulator's pty (firmware detected); checks the safe stop afterwards."""
    robot = ego.Robot(emulator.path, link_settings=IN_PROCESS_LINK)
    try:
        yield robot
    finally:
        robot.close()
    assert_stopped(emulator.world)


@pytest.fixture
def builtin_sim_robot() -> Iterator[ego.Robot]:
    """``Robot("sim")`` with the default settings: the built-in emulator (``world_of``)."""
    robot = ego.Robot("sim", seed=SEED)
    world = world_of(robot)
    try:
        yield robot
    finally:
        robot.close()
    assert_stopped(world)


@pytest.fixture
def overo_emulator() -> Iterator[Emulator]:
    """The stock GCtronic firmware in Overo mode (selector 10)."""
    with Emulator("gctronic", seed=SEED) as emu:
        yield emu


@pytest.fixture
def overo_robot(overo_emulator: Emulator) -> Iterator[ego.Robot]:
    robot = ego.Robot(overo_emulator.path, link_settings=IN_PROCESS_LINK)
    try:
        yield robot
    finally:
        robot.close()
    assert_stopped(overo_emulator.world)
