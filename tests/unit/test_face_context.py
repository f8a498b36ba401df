"""The faces' context (ego.faces.default_robot.FaceContext): options and robot, no module global.

Each context holds its own options and robot; ``ego run`` makes one for its controller
and passes the options explicitly; the C-style functions find the current one through a
ContextVar, and the run's duration is cut off in one place for every face.
"""

from __future__ import annotations

import contextvars
import signal
import sys
import textwrap
from collections.abc import Iterator
from pathlib import Path

import pytest

import ego
from ego import webots as wb
from ego.app import cli, runner
from ego.controller import Robot as WebotsRobot
from ego.core import safety
from ego.errors import EgoError
from ego.faces import default_robot
from ego.faces.default_robot import FaceContext, activate, current_context
from ego.faces.runtime import RunOptions


@pytest.fixture
def fresh() -> Iterator[FaceContext]:
    """A context of its own for the test, active while it runs, closed after."""
    context = FaceContext(RunOptions(port="sim", seed=1))
    with activate(context):
        yield context
    context.close()


def test_two_contexts_do_not_share_a_robot() -> None:
    first, second = FaceContext(RunOptions(port="sim", seed=1)), FaceContext()
    second.options = RunOptions(port="sim", seed=2)
    try:
        one, two = first.open_robot(), second.open_robot()
        assert one is not two
        assert first.get() is one and second.get() is two
        first.close()
        assert not first.is_open() and second.is_open()
        assert two.step(32) == 0  # closing one context left the other's robot alone
        with pytest.raises(EgoError, match="no robot is open"):
            first.get()
    finally:
        first.close()
        second.close()
    assert not second.is_open()


def test_the_c_style_faces_act_on_the_active_context_only() -> None:
    first, second = FaceContext(RunOptions(port="sim", seed=1)), FaceContext()
    try:
        with activate(first):
            assert wb.wb_robot_init() == 1
            assert default_robot.get() is first.get()
            with activate(second):
                assert current_context() is second
                assert not default_robot.is_open()  # first's robot is not second's
                assert wb.wbr_init("/nonexistent/ego-port") == 0
                assert wb.wbr_has_failed()
            assert current_context() is first
            assert not wb.wbr_has_failed()  # the failure was second's
            assert wb.wb_robot_step(32) == 0
    finally:
        first.close()
        second.close()


def test_a_new_contextvars_context_gets_its_own_face_context(fresh: FaceContext) -> None:
    assert current_context() is fresh
    other = contextvars.Context().run(current_context)
    assert other is not fresh
    assert other.options == RunOptions() and not other.is_open()


def test_the_current_contexts_options_are_read_and_set_in_one_place(fresh: FaceContext) -> None:
    assert default_robot.current_options() is fresh.options
    options = RunOptions(port="sim", seed=5)
    default_robot.set_options(options)
    assert fresh.options is options
    with activate(FaceContext()):
        assert default_robot.current_options() is not options


def test_the_webots_robot_takes_its_options_explicitly(fresh: FaceContext) -> None:
    fresh.options = RunOptions(port="/nonexistent/ego-port")  # would fail if read
    robot = WebotsRobot(options=RunOptions(port="sim", seed=1, basic_time_step_ms=16))
    try:
        assert robot.getBasicTimeStep() == 16.0
    finally:
        robot.cleanup()


CONTROLLER = """
    import sys

    from controller import Robot
    from ego.faces import default_robot

    robot = Robot()
    context = default_robot.current_context()
    with open(sys.argv[1], "w") as out:
        out.write(f"{robot.getBasicTimeStep()} {context.options.duration_s} {id(context)}")
    while robot.step(16) != -1:
        pass
"""


def test_ego_run_gives_the_controller_its_options_in_a_context_of_its_own(
    tmp_path: Path, fresh: FaceContext
) -> None:
    script = tmp_path / "controller.py"
    script.write_text(textwrap.dedent(CONTROLLER))
    report = tmp_path / "report.txt"
    robots: list[ego.Robot] = []
    options = RunOptions(
        port="sim", seed=1, duration_s=0.048, basic_time_step_ms=16, on_robot=[robots.append]
    )
    outer_options = fresh.options
    took_signals = signal.getsignal(signal.SIGTERM) is signal.SIG_DFL
    try:
        runner.run_controller(script, options, [str(report)])
    finally:
        if took_signals:  # ego run takes them for good: give them back for the next tests
            safety.uninstall_signal_handlers()
    step, duration, context_id = report.read_text().split()
    assert (float(step), float(duration)) == (16.0, 0.048)
    assert int(context_id) != id(fresh)  # the run's own context...
    assert current_context() is fresh and fresh.options is outer_options  # ...gone after
    assert not fresh.is_open()
    assert len(robots) == 1 and robots[0].time_s == pytest.approx(0.048)


OPTIONS_REPORTER = """
    import sys

    from ego.faces import default_robot

    options = default_robot.current_context().options
    with open(sys.argv[1], "w") as out:
        out.write(f"{options.port} {options.duration_s} {options.basic_time_step_ms}")
"""


def test_the_ego_run_command_passes_the_options_it_parsed(
    tmp_path: Path, fresh: FaceContext
) -> None:
    script = tmp_path / "c.py"
    script.write_text(textwrap.dedent(OPTIONS_REPORTER))
    report = tmp_path / "options.txt"
    outer_options = fresh.options
    took_signals = signal.getsignal(signal.SIGTERM) is signal.SIG_DFL
    interval = sys.getswitchinterval()  # ego run tunes the process for stepping
    args = ["run", "--port", "sim", "--duration", "1.5", "--time-step", "16", str(script),
            str(report)]  # fmt: skip
    try:
        assert cli.main(args) == 0
    finally:
        sys.setswitchinterval(interval)
        if took_signals:  # ego run takes them for good: give them back for the next tests
            safety.uninstall_signal_handlers()
    assert report.read_text().split() == ["sim", "1.5", "16.0"]
    assert fresh.options is outer_options  # nothing was set behind the call


# -- the duration cutoff: one function for every face --------------------------------------


@pytest.mark.parametrize(
    ("duration_s", "time_s", "up"),
    [(None, 1e9, False), (0.5, 0.0, False), (0.5, 0.48, False), (0.5, 0.5, True), (0.5, 0.6, True)],
)
def test_time_is_up_once_the_duration_is_used(
    duration_s: float | None, time_s: float, up: bool
) -> None:
    assert RunOptions(duration_s=duration_s).time_is_up(time_s) is up


def test_both_faces_end_the_run_where_time_is_up_says(fresh: FaceContext) -> None:
    asked: list[float] = []

    class UpAfterFirst(RunOptions):
        def time_is_up(self, time_s: float) -> bool:
            asked.append(time_s)
            return time_s > 0

    fresh.options = UpAfterFirst(port="sim", seed=1)
    assert wb.wb_robot_init() == 1
    assert wb.wb_robot_step(32) == 0
    assert wb.wb_robot_step(32) == -1 and not fresh.is_open()
    robot = WebotsRobot(options=UpAfterFirst(port="sim", seed=1))
    try:
        assert robot.step(32) == 0
        assert robot.step(32) == -1
    finally:
        robot.cleanup()
    assert asked == [0.0, 0.032, 0.0, 0.032]
