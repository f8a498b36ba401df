"""However a controller process ends, the robot stops and its LEDs go off (issue 3, item 6).

The emulator runs in this process, so the test sees the world; the controller runs in a
subprocess on the emulator's pty, is told (or made) to end, and the world must then show
both wheels at 0 and every LED off.
"""

from __future__ import annotations

import select
import signal
import subprocess
import sys
from collections.abc import Callable
from pathlib import Path

import pytest
from helpers import spawn

from firmware_sim import Emulator, World

CONTROLLERS = Path(__file__).parent / "controllers"


def wait_for_running(proc: subprocess.Popen[str], timeout_s: float = 10.0) -> None:
    """Block until the controller prints "running" (it has stepped), within a bound."""
    assert proc.stdout is not None
    ready, _, _ = select.select([proc.stdout], [], [], timeout_s)
    line = proc.stdout.readline() if ready else ""
    if line.strip() != "running":
        proc.kill()
        _, err = proc.communicate(timeout=10)
        pytest.fail(f"the controller did not start: {line!r}\n{err}")


def is_running(world: World) -> bool:
    return world.speeds != (0, 0) and all(world.leds)


def is_stopped(world: World) -> bool:
    return world.speeds == (0, 0) and not any(world.leds)


@pytest.mark.parametrize(
    ("sig", "exit_code"),
    [(signal.SIGTERM, 128 + signal.SIGTERM), (signal.SIGINT, 130)],
    ids=["SIGTERM", "SIGINT"],
)
def test_a_killed_controller_stops_the_robot(
    ego_command: list[str],
    emulator: Emulator,
    world: World,
    tmp_path: Path,
    wait_until: Callable[..., bool],
    sig: signal.Signals,
    exit_code: int,
) -> None:
    run = [*ego_command, "run", "--port", emulator.path, str(CONTROLLERS / "forever_controller.py")]
    with spawn(run, tmp_path) as proc:
        wait_for_running(proc)
        assert wait_until(lambda: is_running(world)), (world.speeds, world.leds)
        assert world.speeds == (318, -318)  # 2 rad/s

        proc.send_signal(sig)
        assert proc.wait(timeout=10) == exit_code

    assert wait_until(lambda: is_stopped(world)), (world.speeds, world.leds)


def test_a_controller_that_raises_stops_the_robot(
    ego_command: list[str],
    emulator: Emulator,
    world: World,
    tmp_path: Path,
    wait_until: Callable[..., bool],
) -> None:
    run = [*ego_command, "run", "--port", emulator.path, str(CONTROLLERS / "raising_controller.py")]
    with spawn(run, tmp_path) as proc:
        wait_for_running(proc)
        assert wait_until(lambda: is_running(world)), (world.speeds, world.leds)

        _, err = proc.communicate("go\n", timeout=10)  # the controller then raises
        assert proc.returncode == 1
        assert "RuntimeError: a bug in the controller" in err

    assert wait_until(lambda: is_stopped(world)), (world.speeds, world.leds)


def test_a_plain_robot_script_killed_with_sigterm_stops_the_robot(
    emulator: Emulator, world: World, tmp_path: Path, wait_until: Callable[..., bool]
) -> None:
    script = [sys.executable, str(CONTROLLERS / "plain_robot_script.py"), emulator.path]
    with spawn(script, tmp_path) as proc:
        wait_for_running(proc)
        assert wait_until(lambda: is_running(world)), (world.speeds, world.leds)
        assert world.speeds == (300, -300)

        proc.send_signal(signal.SIGTERM)
        assert proc.wait(timeout=10) == 128 + signal.SIGTERM

    assert wait_until(lambda: is_stopped(world)), (world.speeds, world.leds)
