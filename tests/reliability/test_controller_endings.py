"""However a controller ends, short of SIGKILL, the wheels stop and every LED goes off.

Each test starts a controller process on the emulated dsPIC's pty (the emulator runs in
this process, so its world is the ground truth), lets it end the way real controllers do,
and reads the wheels and LEDs only after that process has exited: nothing the test does
can stop the robot in its place. None of the controllers stops the robot itself (see
controllers/ending_controller.py); ego must.

The signals are every asynchronous one whose default action ends a process
(``ego.core.safety.TERMINATING_SIGNALS``). Python itself ignores SIGPIPE and SIGXFSZ from
start-up (a failed write raises instead), so those are tested for that: they neither end
the controller nor stop its robot.
"""

from __future__ import annotations

import os
import select
import signal
import subprocess
import sys
import threading
from collections.abc import Iterator
from pathlib import Path

import pytest
from helpers import ego_command, spawn, wait_until

import ego
from ego.core.safety import TERMINATING_SIGNALS
from ego.errors import PortBusyError
from firmware_sim import Emulator, World

CONTROLLER = Path(__file__).parent / "controllers" / "ending_controller.py"
#: The LEDs every style switches on (led1 on the ring, led8 the body LED).
LIT = (1, 8)
#: What a Python process ignores from start-up (this one, as the controller's).
IGNORED = [s for s in TERMINATING_SIGNALS if signal.getsignal(s) is signal.SIG_IGN]
ENDING = [s for s in TERMINATING_SIGNALS if s not in IGNORED]


@pytest.fixture
def emulator() -> Iterator[Emulator]:
    with Emulator("webots", seed=1) as emu:
        yield emu


def _env(port: str) -> dict[str, str]:
    return {**os.environ, "EGO_PORT": port}


def _ego_run(emu: Emulator, style: str) -> list[str]:
    return [*ego_command(), "run", "--port", emu.path, str(CONTROLLER), style]


def _python(style: str) -> list[str]:
    return [sys.executable, str(CONTROLLER), style]


def _wait_running(proc: subprocess.Popen[str], world: World) -> None:
    assert proc.stdout is not None
    ready, _, _ = select.select([proc.stdout], [], [], 15.0)
    line = proc.stdout.readline() if ready else ""
    if line.strip() != "running":
        proc.kill()
        _, err = proc.communicate(timeout=10)
        pytest.fail(f"the controller did not start: {line!r}\n{err}")
    assert wait_until(lambda: world.speeds != (0, 0) and all(world.leds[i] for i in LIT)), (
        f"the controller did not drive: {world.speeds}, {world.leds}"
    )


def _assert_stopped_now(world: World) -> None:
    """The robot as the controller left it: no polling, the process is already gone."""
    assert world.speeds == (0, 0), f"wheels left turning at {world.speeds}"
    assert not any(world.leds), f"LEDs left on: {world.leds}"


def _run_to_end(args: list[str], emu: Emulator, tmp_path: Path) -> subprocess.CompletedProcess[str]:
    proc = subprocess.run(
        args, cwd=tmp_path, env=_env(emu.path), capture_output=True, text=True, timeout=60
    )
    assert "running" in proc.stdout, proc.stderr
    return proc


@pytest.mark.parametrize(
    ("style", "runner"),
    [
        ("webots-ends", "ego run"),
        ("webots-main", "ego run"),
        ("plain-function", "ego run"),
        ("plain-function", "python"),
    ],
)
def test_a_controller_that_simply_ends_leaves_the_robot_stopped(
    emulator: Emulator, tmp_path: Path, style: str, runner: str
) -> None:
    args = _ego_run(emulator, style) if runner == "ego run" else _python(style)
    proc = _run_to_end(args, emulator, tmp_path)
    assert proc.returncode == 0, proc.stderr
    _assert_stopped_now(emulator.world)


@pytest.mark.parametrize("runner", ["ego run", "python"])
def test_a_controller_that_raises_leaves_the_robot_stopped(
    emulator: Emulator, tmp_path: Path, runner: str
) -> None:
    style = "plain-raises"
    args = _ego_run(emulator, style) if runner == "ego run" else _python(style)
    proc = _run_to_end(args, emulator, tmp_path)
    assert proc.returncode == 1
    assert "a bug in the controller" in proc.stderr
    _assert_stopped_now(emulator.world)


@pytest.mark.parametrize("sig", ENDING, ids=lambda s: s.name)
def test_each_terminating_signal_stops_the_robot_then_ends_the_run(
    emulator: Emulator, tmp_path: Path, sig: signal.Signals
) -> None:
    with spawn(_ego_run(emulator, "webots-forever"), tmp_path) as proc:
        _wait_running(proc, emulator.world)
        proc.send_signal(sig)
        assert proc.wait(timeout=15) == 128 + sig
    _assert_stopped_now(emulator.world)


@pytest.mark.parametrize("sig", [signal.SIGHUP, signal.SIGTERM], ids=lambda s: s.name)
def test_a_plain_script_stops_its_robot_on_a_signal(
    emulator: Emulator, tmp_path: Path, sig: signal.Signals
) -> None:
    saved = os.environ.get("EGO_PORT")
    os.environ["EGO_PORT"] = emulator.path  # spawn() passes this process's environment
    try:
        with spawn(_python("plain-forever"), tmp_path) as proc:
            _wait_running(proc, emulator.world)
            proc.send_signal(sig)
            assert proc.wait(timeout=15) == 128 + sig
    finally:
        if saved is None:
            os.environ.pop("EGO_PORT")
        else:
            os.environ["EGO_PORT"] = saved
    _assert_stopped_now(emulator.world)


def test_python_ignores_sigpipe_and_sigxfsz() -> None:
    assert {signal.SIGPIPE, signal.SIGXFSZ} <= set(IGNORED)


@pytest.mark.parametrize("sig", IGNORED, ids=lambda s: s.name)
def test_a_signal_python_ignores_neither_ends_nor_stops_the_controller(
    emulator: Emulator, tmp_path: Path, sig: signal.Signals
) -> None:
    with spawn(_ego_run(emulator, "webots-forever"), tmp_path) as proc:
        _wait_running(proc, emulator.world)
        proc.send_signal(sig)
        with pytest.raises(subprocess.TimeoutExpired):
            proc.wait(timeout=0.5)
        assert emulator.world.speeds == (318, -318)  # still driving, as it was told
        proc.send_signal(signal.SIGTERM)
        assert proc.wait(timeout=15) == 128 + signal.SIGTERM
    _assert_stopped_now(emulator.world)


def test_a_second_controller_on_the_same_port_is_refused(
    emulator: Emulator, tmp_path: Path
) -> None:
    """The first keeps stepping without a fault while the second is turned away."""
    stop = threading.Event()
    with ego.Robot(emulator.path, handle_signals=False) as first:
        first.motors.set_speed(200, 200)
        first.proximity.enable(32)
        stepper = threading.Thread(target=lambda: [first.step(32) for _ in iter(stop.is_set, True)])
        stepper.start()
        try:
            assert wait_until(lambda: emulator.world.speeds == (200, 200))
            proc = _run_to_end_refused(_ego_run(emulator, "webots-forever"), emulator, tmp_path)
            steps_before = first.steps
            assert wait_until(lambda: first.steps > steps_before + 3)
        finally:
            stop.set()
            stepper.join(timeout=10)
        assert proc.returncode == 1
        assert f"is held by process {os.getpid()}" in proc.stderr
        assert emulator.world.speeds == (200, 200)  # the second never drove
        # Nothing the second wrote reached the line: no stray bytes, no restart. (A reply
        # late for want of a core, on a busy machine, is retried: a timeout or a short
        # reply, not this.)
        stats = first.channel.stats
        assert set(stats.faults) <= {"LinkTimeoutError", "ShortReplyError"}, stats.faults
        with pytest.raises(PortBusyError, match="this process"):
            ego.Robot(emulator.path, handle_signals=False)


def _run_to_end_refused(
    args: list[str], emu: Emulator, tmp_path: Path
) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        args, cwd=tmp_path, env=_env(emu.path), capture_output=True, text=True, timeout=60
    )


@pytest.mark.parametrize(
    "sig", [signal.SIGHUP, signal.SIGQUIT, signal.SIGUSR1], ids=lambda s: s.name
)
def test_ego_serve_stops_the_robot_on_every_terminating_signal(
    emulator: Emulator, tmp_path: Path, sig: signal.Signals
) -> None:
    """The server on the robot is a controller too: its ssh session dropping must not leave
    the wheels turning for the PC that drove them."""
    from ego.backends.remote.channel import RemoteChannel
    from ego.seam.batch import Request
    from ego.seam.profile import Command
    from ego.serial.protocol import encode_batch

    args = [*ego_command(), "serve", "--port", emulator.path, "--listen", "tcp://127.0.0.1:0"]
    with spawn(args, tmp_path) as proc:
        assert proc.stderr is not None
        url = ""
        for line in proc.stderr:
            if " on tcp://" in line:
                url = line.rsplit(" on ", 1)[1].strip()
                break
        assert url, "ego serve did not start"
        link = RemoteChannel.from_url(url)
        try:
            batch = encode_batch(
                [Request(Command.SET_SPEED, (300, -300)), Request(Command.SET_LED, (1, 1))],
                link.profile,
            )
            link.exchange(batch)
            assert wait_until(lambda: emulator.world.speeds == (300, -300))
            proc.send_signal(sig)
            assert proc.wait(timeout=15) == 0
        finally:
            link.close()
    _assert_stopped_now(emulator.world)
