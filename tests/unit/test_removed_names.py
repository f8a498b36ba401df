"""Issue 35: the names kept for an unreleased 0.1.0 are gone. What a Robot steps through
is ``Robot.channel`` (not ``Robot.link``), what its simulator knows is
``Robot.ground_truth`` (not ``Robot.emulator``), and the profiles are named after their
firmwares only (``thesis`` and ``gctronic-overo`` are refused like any unknown name)."""

from __future__ import annotations

import pytest

import ego
from ego.errors import OutOfRangeError
from ego.seam.channel import ChannelBase
from firmware_sim import Emulator
from firmware_sim.dspic import firmware_name


def test_the_channel_is_robot_channel_and_the_old_names_are_gone() -> None:
    with Emulator("webots", seed=1) as emu, ego.Robot(emu.path) as robot:
        assert isinstance(robot.channel, ChannelBase)
        assert robot.ground_truth is None  # a robot on a pty: no simulator behind it
        for old in ("link", "emulator", "link_lock"):
            assert not hasattr(robot, old), old


@pytest.mark.parametrize("old", ["thesis", "gctronic-overo"])
def test_the_old_profile_names_are_refused(old: str) -> None:
    with pytest.raises(OutOfRangeError, match=f"firmware {old!r} is not one of auto, "):
        ego.Firmware.choose(old)
    with pytest.raises(ValueError, match=f"firmware {old!r} is not one of"):
        firmware_name(old)


@pytest.mark.parametrize("old", ["thesis", "gctronic-overo"])
def test_the_command_line_refuses_the_old_profile_names(
    old: str, capsys: pytest.CaptureFixture[str]
) -> None:
    from ego.app.cli import build_parser

    with pytest.raises(SystemExit):
        build_parser().parse_args(["serve", "--firmware", old])
    assert f"invalid choice: '{old}'" in capsys.readouterr().err
