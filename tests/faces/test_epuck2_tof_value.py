"""Issue 32, item 3: the e-puck2's ``tof`` under the Webots face is the robot's millimetres,
unchanged, over USB (the emulator's pty), WiFi (its radio on loopback) and the emulator
itself (``port sim``). Webots' own e-puck2 remote control does the same (``Wrapper.cpp``,
``robotStep``); the PROTO's lookup table models the sensor in simulation and applying it
to a real reading gave 141.58 for 123 mm."""

from __future__ import annotations

import os
from collections.abc import Iterator

import pytest

import ego
from ego.controller import Robot as WebotsRobot
from ego.controller.distance_sensor import DistanceSensor
from ego.faces import default_robot, runtime
from firmware_sim.epuck2 import Epuck2Emulator
from firmware_sim.worlds import load_world


@pytest.fixture(params=["usb", "wifi", "sim"])
def port(request: pytest.FixtureRequest) -> Iterator[tuple[str, Epuck2Emulator | None]]:
    if request.param == "sim":
        yield "sim", None
        return
    wifi = request.param == "wifi"
    # A quiet world: each ToF reading (every 33 ms) is the one ego holds, however late
    # the radio's stream brings it.
    world = load_world("arena", seed=4)
    world.noise = False
    with Epuck2Emulator(world, seed=4, wifi=wifi, port=0) as emulator:
        if wifi:
            assert emulator.wifi_address is not None
            host, number = emulator.wifi_address
            yield f"epuck2://{host}:{number}", emulator
        else:
            assert emulator.pty_path is not None
            yield os.path.realpath(emulator.pty_path), emulator


def test_tof_get_value_is_the_robots_millimetres(
    port: tuple[str, Epuck2Emulator | None],
) -> None:
    url, emulator = port
    cores: list[ego.Robot] = []
    sim = {"robot": "epuck2", "seed": 4, "world": "arena"} if url == "sim" else {}
    default_robot.set_options(runtime.RunOptions(port=url, on_robot=[cores.append], **sim))  # type: ignore[arg-type]
    controller = WebotsRobot()
    try:
        tof = controller.getDevice("tof")
        assert isinstance(tof, DistanceSensor)
        tof.enable(32)
        controller.step(32)
        (core,) = cores
        mm = core.tof.distance_mm
        assert 0 < mm < 2000  # the arena puts a wall in range
        value = tof.getValue()
        assert value == mm and isinstance(value, float | int)
        if emulator is not None:
            assert value == emulator.robot.tof.distance_mm()
        # The lookup table is still the PROTO's, as getLookupTable() gives it.
        assert tof.getLookupTable() == [0.0, 19.8, 0.0, 2.0, 2000.0, 0.0]
    finally:
        controller.cleanup()
        default_robot.set_options(runtime.RunOptions())
