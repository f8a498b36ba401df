"""No hidden process state (issue 24, item 7): the environment is read in one module, and
what holds robots and radios is an explicit owner, never a registry in some module.

The environment is read by ego.core.environment only, at the edge (a Robot opened
without one, ego run, ego serve, a face's context) and passed down; the robots open in
the process are ego.core.safety.OPEN_ROBOTS's; a robot's radio is its Webots Robot's.
"""

from __future__ import annotations

import ast
import re
from pathlib import Path

import pytest
from helpers import REPOSITORY, needs_source_tree

import ego
from ego.controller import Robot as WebotsRobot
from ego.core.environment import VARIABLES, Environment, read_environment
from ego.core.robot import Robot
from ego.core.safety import OPEN_ROBOTS, OpenRobots, RobotKeeper
from ego.faces.default_robot import FaceContext, activate
from ego.faces.runtime import RunOptions

ROOT = REPOSITORY
#: ego as installed: the checkout's src/ego, or on a board the wheel's.
SRC = Path(ego.__file__).resolve().parent
#: The one reader, and the two modules that write a child process's environment.
READER = SRC / "core" / "environment.py"
CHILD_ENVIRONMENTS = {SRC / "app" / "swarm.py", SRC / "servers" / "supervisor.py"}
#: Variables of the test and browser harness (README, "Develop"), not of ego itself.
# Read by the tests and by the project's own scripts (tools/board_check.sh), not by ego.
HARNESS = {"EGO_CHROMIUM", "EGO_REQUIRE_BROWSER", "EGO_BOARD_CACHE", "EGO_BOARD_REUSE"}


def _reads_environment(path: Path) -> list[int]:
    """The lines of ``path`` that name os.environ or os.getenv."""
    lines = []
    for node in ast.walk(ast.parse(path.read_text())):
        if (
            isinstance(node, ast.Attribute)
            and node.attr in ("environ", "getenv", "environb")
            and isinstance(node.value, ast.Name)
            and node.value.id == "os"
        ):
            lines.append(node.lineno)
    return lines


def test_only_the_environment_module_reads_the_environment() -> None:
    readers = {
        f"{path.relative_to(SRC)}:{line}"
        for path in SRC.rglob("*.py")
        if path != READER and path not in CHILD_ENVIRONMENTS
        for line in _reads_environment(path)
    }
    assert readers == set()
    assert _reads_environment(READER)  # the check sees a reader


@needs_source_tree
def test_every_documented_variable_is_read_there() -> None:
    texts = [ROOT / "README.md", *(ROOT / "docs").rglob("*.md")]
    documented = {name for path in texts for name in re.findall(r"EGO_[A-Z_]+", path.read_text())}
    assert documented - HARNESS <= set(VARIABLES)
    assert {"EGO_PORT", "EGO_SECRET_FILE", "EGO_RADIO", "EGO_ZENOH_CONNECT"} <= documented


def test_the_environment_reads_what_it_is_given() -> None:
    env = read_environment({
        "EGO_PORT": "/dev/rfcomm0", "EGO_CAMERA": "none", "EGO_RADIO": "none",
        "EGO_ZENOH_LISTEN": "tcp/127.0.0.1:1,,tcp/127.0.0.1:2", "EGO_SECRET_FILE": "",
        "HOME": "/root",
    })  # fmt: skip
    assert env == Environment(port="/dev/rfcomm0", camera="none", radio=False,
                              zenoh_listen=("tcp/127.0.0.1:1", "tcp/127.0.0.1:2"))  # fmt: skip
    assert read_environment({}) == Environment()


class Part:
    """Something a keeper closes."""

    def __init__(self) -> None:
        self.closes = 0

    def close(self) -> None:
        self.closes += 1


def test_a_registry_hands_what_opens_to_its_active_keepers_only() -> None:
    registry = OpenRobots()
    before, during = Part(), Part()
    registry.opened(before)
    with RobotKeeper(registry) as kept:
        registry.opened(during)
        assert kept.robots == [during]
    assert (before.closes, during.closes) == (0, 1)
    assert set(registry.robots()) == {before, during}  # open until they say they closed
    registry.closed(during)
    registry.close_all()
    assert registry.robots() == [before] and before.closes == 1


def test_a_robot_tells_the_process_registry_when_it_opens_and_closes() -> None:
    with RobotKeeper() as kept:
        robot = Robot("sim", seed=1)
        assert kept.robots == [robot] and robot in OPEN_ROBOTS.robots()
    assert robot.closed and robot not in OPEN_ROBOTS.robots()


@pytest.fixture
def radio_context() -> FaceContext:
    return FaceContext(RunOptions(port="sim", seed=1), read_environment({}))


def test_a_robots_emitter_and_receiver_share_the_radio_its_webots_robot_owns(
    radio_context: FaceContext,
) -> None:
    pytest.importorskip("zenoh")  # the radio exists with eclipse-zenoh installed only
    with activate(radio_context):
        robot = WebotsRobot()
    try:
        emitter, receiver = robot.getDevice("emitter"), robot.getDevice("receiver")
        assert emitter._radio is receiver._radio is robot._radio  # type: ignore[union-attr]
    finally:
        robot.cleanup()


def test_ego_radio_none_in_the_faces_environment_leaves_the_robot_without_a_radio() -> None:
    context = FaceContext(RunOptions(port="sim", seed=1), read_environment({"EGO_RADIO": "none"}))
    with activate(context):
        robot = WebotsRobot()
    try:
        assert robot.getDevice("emitter") is None
    finally:
        robot.cleanup()
