"""``ego.Robot("tcp://...")``, a Webots controller unchanged over the network, robot groups."""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np
import pytest
from remote_helpers import ServeFactory, wait_for

import ego
import ego.examples
from ego.app.runner import run_controller
from ego.camera import Camera
from ego.core.group import RobotGroup, step_all
from ego.faces import runtime
from ego.serial.link import LinkSettings
from firmware_sim.camera import SimulatedSource

#: A robot whose server vanished gives up quickly in tests.
QUICK_LOSS = LinkSettings(retries=1, reconnect_timeout_s=0.3)
OBSTACLE_AVOIDANCE = Path(ego.examples.__file__).parent / "obstacle_avoidance.py"


def test_robot_on_a_url_reads_its_sensors_and_drives(serve: ServeFactory, kind: str) -> None:
    served = serve(kinds=(kind,))
    with ego.Robot(served.url, handle_signals=False) as robot:
        robot.proximity.enable(32)
        robot.motors.set_speed(300, -300)
        assert robot.step(32) == 0
        assert len(robot.proximity.values) == 8
        assert served.emu.history[-1].commands.startswith("D")
        wait_for(lambda: served.emu.world.speeds == (300, -300), 1.0)
        for _ in range(3):
            assert robot.step(32) == 0
    assert served.emu.world.speeds == (0, 0)  # leaving the with-block stopped it
    assert served.server.controller is None


def test_webots_controller_runs_unchanged_over_the_network(serve: ServeFactory, kind: str) -> None:
    served = serve(kinds=(kind,))
    options = runtime.RunOptions(port=served.url, duration_s=0.64, basic_time_step_ms=32)
    run_controller(OBSTACLE_AVOIDANCE, options)
    batches = [r.commands for r in served.emu.history]
    steps_with_proximity = sum("N" in c for c in batches)
    assert 15 <= steps_with_proximity <= 21  # 0.64 s of 32 ms steps
    assert any(c.startswith("D") for c in batches)  # it drove
    assert served.emu.world.speeds == (0, 0)  # and was stopped when it ended
    assert served.server.controller is None


def test_robot_camera_is_fetched_from_the_server(serve: ServeFactory) -> None:
    served = serve(sim_camera=True)
    with ego.Robot(served.url, handle_signals=False) as robot:
        camera = robot.camera
        camera.set_size(160, 120)
        image = camera.capture().copy()
    with Camera(source=SimulatedSource(served.emu.world), width=160, height=120) as local:
        assert np.array_equal(image, local.capture())


def test_group_steps_robots_together_each_on_its_own_server(serve: ServeFactory) -> None:
    one, two = serve(kinds=("tcp",)), serve(kinds=("udp",))
    with (
        ego.Robot(one.url, handle_signals=False) as a,
        ego.Robot(two.url, handle_signals=False) as b,
        RobotGroup([a, b]) as group,
    ):
        a.motors.set_speed(100, 100)
        b.motors.set_speed(-100, -100)
        a.proximity.enable(32)
        b.proximity.enable(32)
        start = time.monotonic()
        for _ in range(10):
            assert group.step(32) == 0
        elapsed = time.monotonic() - start
        assert group.results == (0, 0)
        assert (a.steps, b.steps) == (10, 10)
        assert elapsed < 10 * 0.032 * 1.75  # in parallel, not one after the other
        wait_for(lambda: one.emu.world.speeds == (100, 100), 1.0)
        wait_for(lambda: two.emu.world.speeds == (-100, -100), 1.0)


def test_group_step_is_minus_one_once_a_robot_is_lost(serve: ServeFactory) -> None:
    one, two = serve(kinds=("tcp",)), serve(kinds=("udp",))
    with (
        ego.Robot(one.url, handle_signals=False, link_settings=QUICK_LOSS) as a,
        ego.Robot(two.url, handle_signals=False, link_settings=QUICK_LOSS) as b,
        RobotGroup([a, b]) as group,
    ):
        a.proximity.enable(32)
        b.proximity.enable(32)
        assert group.step(32) == 0
        two.thread.stop()  # robot b's server goes away
        assert wait_for_minus_one(group) < 3.0
        assert group.lost == (b,)
        assert step_all([a], 32) == 0  # the other robot still steps


def wait_for_minus_one(group: RobotGroup[ego.Robot]) -> float:
    start = time.monotonic()
    while group.step(32) != -1:
        if time.monotonic() - start > 5:
            raise AssertionError("the lost robot was never reported")
    return time.monotonic() - start


class _Fake:
    def __init__(self, results: list[int | BaseException]) -> None:
        self.results = results
        self.calls = 0

    def step(self, ms: int) -> int:
        self.calls += 1
        result = self.results.pop(0)
        if isinstance(result, BaseException):
            raise result
        return result


def test_group_raises_one_robots_error_after_every_robot_stepped() -> None:
    failing, fine = _Fake([RuntimeError("boom")]), _Fake([0])
    with RobotGroup([failing, fine]) as group, pytest.raises(RuntimeError, match="boom"):
        group.step(10)
    assert fine.calls == 1


def test_empty_group_is_refused() -> None:
    with pytest.raises(ValueError, match="at least one robot"):
        RobotGroup([])


def test_closed_group_refuses_to_step() -> None:
    group = RobotGroup([_Fake([0])])
    group.close()
    group.close()
    with pytest.raises(RuntimeError, match="closed"):
        group.step(10)
