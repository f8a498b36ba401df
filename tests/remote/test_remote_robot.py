"""``ego.Robot("tcp://...")``, a Webots controller unchanged over the network, robot groups."""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np
import pytest
from helpers import wait_until
from remote_helpers import ServeFactory

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
        assert wait_until(lambda: served.emu.world.speeds == (300, -300))
        for _ in range(3):
            assert robot.step(32) == 0
    assert served.emu.world.speeds == (0, 0)  # leaving the with-block stopped it
    assert served.server.controller is None


def test_webots_controller_runs_unchanged_over_the_network(serve: ServeFactory, kind: str) -> None:
    served = serve(kinds=(kind,))
    options = runtime.RunOptions(port=served.url, duration_s=0.64, basic_time_step_ms=32)
    run_controller(OBSTACLE_AVOIDANCE, options)
    batches = [r.commands for r in served.emu.history]
    # 0.64 s of controller time in 32 ms steps: 20 steps, however slow the machine. The
    # server counts the steps it ran (a retransmitted one is answered from its cache);
    # the emulator's history would count a batch the serial line retried twice.
    assert served.server.stats.steps == 20 + 1, served.server.stats  # and the closing stop
    assert sum("N" in c for c in batches) >= 20  # each step read the proximity sensors
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
        assert wait_until(lambda: one.emu.world.speeds == (100, 100))
        assert wait_until(lambda: two.emu.world.speeds == (-100, -100))


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
        # Each step waits out QUICK_LOSS's bounded retries and reconnection, then -1.
        assert wait_until(lambda: group.step(32) == -1, interval_s=0), "b was never reported"
        assert group.lost == (b,)
        assert step_all([a], 32) == 0  # the other robot still steps


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
