"""Helpers shared by the test folders: polling the world, child processes, the ego command."""

from __future__ import annotations

import contextlib
import math
import subprocess
import sys
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import pytest

import ego
from firmware_sim import Emulator, World
from firmware_sim.ego_backend import IN_PROCESS_SLACK_S, EmulatorTruth

__all__ = [
    "REPOSITORY",
    "SUBNORMALS",
    "assert_stopped",
    "ego_command",
    "emulator_of",
    "is_stopped",
    "needs_source_tree",
    "run_async",
    "spawn",
    "wait_for_more",
    "wait_until",
    "world_of",
]

#: Whether this process can hold subnormal floats: False when something set the FPU's
#: flush-to-zero mode for the whole process (the armv7 wheel of yarl, which aiohttp pulls
#: in, does on import). Hypothesis refuses a float strategy that allows subnormals then,
#: and advises allow_subnormal=False: float strategies pass allow_subnormal=SUBNORMALS.
#: yarl is imported first (where it is installed), as a later test's aiohttp would: the
#: strategies are built when their module is collected, before that test runs.
with contextlib.suppress(ImportError):
    import yarl  # noqa: F401
SUBNORMALS = math.ulp(0.0) != 0.0

#: The checkout the tests belong to. Where ego under test is that checkout's own source
#: (an editable install: development and every CI job) the tree's README, docs and src are
#: there to be checked; on a board (tools/board_check.sh) ego is the wheel the guide
#: installs and only the tests were copied over, so what reads the tree skips, saying so.
REPOSITORY = Path(__file__).resolve().parents[1]
needs_source_tree = pytest.mark.skipif(
    Path(ego.__file__).resolve().parent != REPOSITORY / "src" / "ego",
    reason="reads the repository (README, docs, src): ego under test is an installed wheel, "
    "as on a board",
)


#: A robot's link to an emulator the test started in its own process, on a real pty: the
#: emulator's banner is 4 ms of line time, so 20 ms of quiet after it is plenty (the
#: default 100 ms suits a real robot); and it answers from threads beside the test's, so
#: a reply may be held up as long as the sim backend allows its own (IN_PROCESS_SLACK_S).
#: Tests of the line's own timing keep a strict link (tests/fakes.py FAST_LINK).
IN_PROCESS_LINK = ego.LinkSettings(
    resync_quiet_s=0.02, reply_timeout_s=ego.LinkSettings().reply_timeout_s + IN_PROCESS_SLACK_S
)


def emulator_of(robot: ego.Robot) -> Emulator:
    """The emulator behind ``Robot("sim")`` (its history, its faults, its I2C bus): the
    sim backend's ground truth keeps it beside what ego reads through the protocol."""
    truth = robot.ground_truth
    assert isinstance(truth, EmulatorTruth) and truth.emulator is not None, truth
    return truth.emulator


def world_of(robot: ego.Robot) -> World:
    """The simulated world behind ``Robot("sim")``, from its ground truth (the sim
    backend's :class:`EmulatorTruth`, which follows ego's GroundTruth protocol)."""
    truth = robot.ground_truth
    assert isinstance(truth, EmulatorTruth), truth
    return truth.world


@contextlib.contextmanager
def spawn(args: list[str], cwd: Path) -> Iterator[subprocess.Popen[str]]:
    """Start a process and never leave it behind (its SIGINT raises KeyboardInterrupt
    however the suite was started: tests/conftest.py's pytest_configure)."""
    proc = subprocess.Popen(
        args, cwd=cwd, stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
        text=True,
    )  # fmt: skip
    try:
        yield proc
    finally:
        if proc.poll() is None:
            proc.kill()
        proc.communicate(timeout=10)


def wait_until(
    condition: Callable[[], object], timeout_s: float = 5.0, interval_s: float = 0.005
) -> bool:
    """Poll ``condition`` until it holds or ``timeout_s`` passes; whether it held (``assert
    wait_until(...), why``). The one waiting helper of the suite.

    An actuator-only batch gets no reply (protocol.md), and another process's robot acts on
    its own time, so tests wait for the world rather than sleep a fixed time. The budget
    is generous on purpose (a loaded machine is slow): it bounds a failure, it measures
    nothing. A timing promise is asserted against the clock the code itself keeps (the
    server's deadman records how long its client was silent), never against how soon
    this loop noticed.
    """
    deadline = time.monotonic() + timeout_s
    while not condition():
        if time.monotonic() > deadline:
            return bool(condition())
        time.sleep(interval_s)
    return True


def wait_for_more(count: Callable[[], int], more: int, timeout_s: float = 20.0) -> bool:
    """Wait until ``count()`` has grown by ``more`` from now; whether it did (``assert
    wait_for_more(...), why``).

    ``count`` tallies events that would make a bug show: the batches the emulator
    received, the steps the controller took, the samples a page got. "Nothing happened"
    is then asserted over that many real chances for it to happen, not over a time that
    a loaded machine may fill with nothing at all.
    """
    start = count()
    return wait_until(lambda: count() >= start + more, timeout_s)


def is_stopped(world: World) -> bool:
    return world.speeds == (0, 0) and not any(world.leds)


def assert_stopped(world: World) -> None:
    assert wait_until(lambda: is_stopped(world)), (
        f"the robot was left running: speeds {world.speeds}, LEDs {world.leds}"
    )


def ego_command() -> list[str]:
    """The installed ``ego`` script beside this Python, else ``python -m ego.app.cli``."""
    script = Path(sys.executable).with_name("ego")
    return [str(script)] if script.is_file() else [sys.executable, "-m", "ego.app.cli"]


def run_async(coroutine: Any, timeout_s: float = 20) -> Any:
    """Run ``coroutine`` to its end on a fresh event loop in a thread of its own (the
    browser tests' Playwright keeps a loop running on the main thread)."""
    import asyncio
    import threading

    result: list[Any] = []
    failure: list[BaseException] = []

    def main() -> None:
        try:
            result.append(asyncio.run(asyncio.wait_for(coroutine, timeout_s)))
        except BaseException as exc:
            failure.append(exc)

    thread = threading.Thread(target=main, name="test-page")
    thread.start()
    thread.join(timeout_s + 5)
    if failure:
        raise failure[0]
    return result[0]


def message_matches(documented: str, actual: str) -> bool:
    """Whether ``actual`` holds a table's documented message pieces, in order (``…``
    skips any text): the guides' and docs/bad_input.md's rows are checked so."""
    position = 0
    for piece in (p.strip() for p in documented.split("…")):
        found = actual.find(piece, position)
        if found < 0:
            return False
        position = found + len(piece)
    return True
