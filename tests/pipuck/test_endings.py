"""Issue 33, safety: the stop (zero speeds, every LED off, a valid checksum) reaches the
Pi-puck's robot however the controller ends, as on the serial line; ``ego run``
supervises by default on the Pi-puck, so even a controller killed outright has its
robot stopped."""

from __future__ import annotations

import os
import signal
from collections.abc import Callable
from pathlib import Path

import pytest
from helpers import wait_until
from pipuck_support import Runner

from firmware_sim.pipuck import PipuckEmulator

DRIVE = """\
from controller import Robot
robot = Robot()
left, right = robot.getDevice("left wheel motor"), robot.getDevice("right wheel motor")
for motor in (left, right):
    motor.setPosition(float("inf"))
    motor.setVelocity(2.0)
robot.getDevice("led1").set(0x00FF00)
robot.getDevice("led0").set(1)
steps = 0
while robot.step(32) != -1:
    steps += 1
    if steps == 20 and "{ending}" == "raise":
        raise RuntimeError("the controller fails")
    if steps == 20 and "{ending}" == "exit":
        raise SystemExit(3)
"""


def _controller(folder: Path, ending: str) -> str:
    path = folder / f"drive_{ending}.py"
    path.write_text(DRIVE.replace("{ending}", ending))
    return str(path)


def _moving(emu: PipuckEmulator) -> bool:
    truth = emu.truth
    return truth.speeds != (0, 0) and truth.rgb_leds[0] == (0, 100, 0)


def _children(pid: int) -> list[int]:
    path = Path(f"/proc/{pid}/task/{pid}/children")
    return [int(p) for p in path.read_text().split()] if path.exists() else []


@pytest.mark.parametrize("ending", ["raise", "exit"])
def test_a_controller_that_fails_or_exits_leaves_its_robot_stopped(
    ending: str, pipuck: Callable[..., PipuckEmulator],
    runner: Callable[[PipuckEmulator], Runner], tmp_path: Path,
) -> None:  # fmt: skip
    emu = pipuck()
    done = runner(emu).ego("run", "--port", "pipuck", "--no-supervised",
                           _controller(tmp_path, ending))  # fmt: skip
    assert done.returncode != 0
    truth = emu.truth
    assert truth.last_was_stop and truth.steps[0] > 0, truth  # it drove, then stopped


@pytest.mark.parametrize("supervised", [True, False])
@pytest.mark.parametrize("signum", [signal.SIGTERM, signal.SIGINT])
def test_a_signal_to_ego_run_stops_the_robot(
    supervised: bool, signum: int, pipuck: Callable[..., PipuckEmulator],
    runner: Callable[[PipuckEmulator], Runner], tmp_path: Path,
) -> None:  # fmt: skip
    emu = pipuck()
    flag = [] if supervised else ["--no-supervised"]
    child = runner(emu).start_ego("run", "--port", "pipuck", *flag,
                                  _controller(tmp_path, "run"))  # fmt: skip
    assert wait_until(lambda: _moving(emu), 30), emu.truth
    child.send_signal(signum)
    child.communicate(timeout=60)
    assert emu.truth.last_was_stop, emu.truth


def test_supervision_is_the_default_and_stops_a_killed_controller(
    pipuck: Callable[..., PipuckEmulator], runner: Callable[[PipuckEmulator], Runner],
    tmp_path: Path,
) -> None:  # fmt: skip
    emu = pipuck()
    child = runner(emu).start_ego("run", "--port", "pipuck", _controller(tmp_path, "run"))
    assert wait_until(lambda: _moving(emu), 30), emu.truth
    controllers = _children(child.pid)
    assert controllers, "ego run on a Pi-puck runs its controller supervised, in a child"
    os.kill(controllers[0], signal.SIGKILL)  # nothing in the controller can run now
    child.communicate(timeout=60)
    assert emu.truth.last_was_stop, emu.truth


def test_a_robot_dropped_without_close_is_stopped_at_exit(
    pipuck: Callable[..., PipuckEmulator], runner: Callable[[PipuckEmulator], Runner],
) -> None:  # fmt: skip
    emu = pipuck()
    seen = runner(emu).script(
        "robot = ego.Robot('pipuck', camera_device='none')\n"
        "robot.motors.set_speed(500, 500)\n"
        "robot.leds.set('led0', 1)\n"
        "robot.step(32)\n"
        "print(json.dumps({'moving': True}))\n"  # and the interpreter exits, robot open
    )
    assert seen == {"moving": True}
    assert emu.truth.last_was_stop, emu.truth


def test_the_stop_at_close_is_sent_whatever_ego_believes(
    pipuck: Callable[..., PipuckEmulator], runner: Callable[[PipuckEmulator], Runner],
) -> None:  # fmt: skip
    """The channel's close sends the all-zero message even when ego thinks the robot is
    already stopped (another program may have moved it meanwhile)."""
    emu = pipuck()
    before = emu.truth.packets
    runner(emu).script(
        "robot = ego.Robot('pipuck', camera_device='none')\n"
        "robot.close()\n"
        "print(json.dumps({}))\n"
    )
    truth = emu.truth
    # the open's stop, the Robot's confirmed stop batch, then the channel's own stop
    assert truth.packets >= before + 3 and truth.last_packet == bytes(20)


def test_ego_run_on_a_pipuck_is_supervised_unless_told_otherwise() -> None:
    from ego.servers.supervisor import wants_supervision

    assert wants_supervision("pipuck") and wants_supervision("/dev/ttyS0")
    assert not wants_supervision("sim") and not wants_supervision("/dev/ttyUSB0")
