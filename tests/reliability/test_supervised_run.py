"""``ego run --supervised``: the robot stops however the controller ends, SIGKILL and a hung
loop included. The emulator runs in this process; its world is read after the fact."""

from __future__ import annotations

import os
import select
import signal
import subprocess
import time
from collections.abc import Callable, Iterator
from pathlib import Path

import pytest
from helpers import ego_command, spawn, wait_until

from firmware_sim import Emulator

CONTROLLER = Path(__file__).parent / "controllers" / "supervised_controller.py"
DEADLINE_MS = 300
#: What the wheels may take beyond an event: the stop batch over the emulated line.
MARGIN_S = 0.15


@pytest.fixture
def emulator() -> Iterator[Emulator]:
    with Emulator("webots", seed=1) as emu:
        yield emu


def _run(emu: Emulator, mode: str, *extra: str) -> list[str]:
    return [
        *ego_command(), "run", "--supervised", "--supervisor-deadline-ms", str(DEADLINE_MS),
        "--port", emu.path, *extra, str(CONTROLLER), mode,
    ]  # fmt: skip


def _controller_pid(proc: subprocess.Popen[str], emu: Emulator) -> int:
    assert proc.stdout is not None
    ready, _, _ = select.select([proc.stdout], [], [], 20.0)
    line = proc.stdout.readline() if ready else ""
    if not line.startswith("running"):
        proc.kill()
        pytest.fail(f"the controller did not start: {line!r}\n{proc.communicate()[1]}")
    assert _until(lambda: emu.world.speeds != (0, 0), 5.0) < 5.0
    return int(line.split()[1])


def _until(condition: Callable[[], object], timeout_s: float) -> float:
    """Seconds until ``condition()`` held (:func:`helpers.wait_until`, every ms), or
    ``timeout_s``: the supervisor is another process, whose clock a test cannot read."""
    start = time.monotonic()
    wait_until(condition, timeout_s, interval_s=0.001)
    return time.monotonic() - start


def test_a_sigkilled_controller_has_its_robot_stopped_at_once(
    emulator: Emulator, tmp_path: Path
) -> None:
    with spawn(_run(emulator, "forever"), tmp_path) as proc:
        pid = _controller_pid(proc, emulator)
        assert pid != proc.pid  # the controller is the supervisor's child
        os.kill(pid, signal.SIGKILL)
        elapsed = _until(lambda: emulator.world.speeds == (0, 0), 3.0)
        assert proc.wait(timeout=15) == 128 + signal.SIGKILL
    assert emulator.world.speeds == (0, 0)
    assert elapsed < MARGIN_S, elapsed  # the socket closed: no deadline to wait for


def test_a_controller_whose_loop_hangs_has_its_robot_stopped_after_the_deadline(
    emulator: Emulator, tmp_path: Path
) -> None:
    with spawn(_run(emulator, "hang"), tmp_path) as proc:
        _controller_pid(proc, emulator)
        elapsed = _until(lambda: emulator.world.speeds == (0, 0), 5.0)
        assert emulator.world.speeds == (0, 0)
        assert proc.poll() is None  # the controller is still there, stuck
        proc.send_signal(signal.SIGTERM)
        assert proc.wait(timeout=15) == 128 + signal.SIGTERM
    # From its last steps (3 x 32 ms after the "running" line) to the stop.
    assert elapsed < 3 * 0.032 + DEADLINE_MS / 1000 + MARGIN_S + 0.2, elapsed


def test_a_controller_that_ends_exits_0_with_its_robot_stopped(
    emulator: Emulator, tmp_path: Path
) -> None:
    with spawn(_run(emulator, "ends"), tmp_path) as proc:
        _controller_pid(proc, emulator)
        assert proc.wait(timeout=15) == 0
    assert emulator.world.speeds == (0, 0)


def test_sigterm_to_the_supervisor_ends_the_controller_and_stops_the_robot(
    emulator: Emulator, tmp_path: Path
) -> None:
    with spawn(_run(emulator, "forever"), tmp_path) as proc:
        pid = _controller_pid(proc, emulator)
        proc.send_signal(signal.SIGTERM)
        assert proc.wait(timeout=15) == 128 + signal.SIGTERM
        with pytest.raises(ProcessLookupError):
            os.kill(pid, 0)  # the controller is gone too
    assert emulator.world.speeds == (0, 0)


@pytest.mark.parametrize("value", ["0", "60001", "ten"])
def test_a_bad_supervisor_deadline_is_refused(value: str, tmp_path: Path) -> None:
    result = subprocess.run(
        [*ego_command(), "run", "--supervisor-deadline-ms", value, str(CONTROLLER), "ends"],
        capture_output=True,
        text=True,
        cwd=tmp_path,
        timeout=30,
    )
    assert result.returncode == 2
    assert "--supervisor-deadline-ms" in result.stderr


def test_supervision_is_the_default_on_the_robots_uart_only() -> None:
    from ego.servers.supervisor import wants_supervision

    assert wants_supervision("/dev/ttyS0") and wants_supervision("/dev/ttyO2")
    assert not wants_supervision("sim")
    assert not wants_supervision("/dev/pts/3")
    assert not wants_supervision("tcp://robot:4242")
