"""Issue 24: what a Robot steps through is ``Robot.channel``; the old name ``Robot.link``
(README's examples read ``robot.link.info``) still works, with a DeprecatedNameWarning."""

from __future__ import annotations

import pytest

import ego
from ego.errors import DeprecatedNameWarning
from ego.seam.channel import ChannelBase
from firmware_sim import Emulator


def test_the_channel_is_robot_channel_and_link_is_its_deprecated_name() -> None:
    with Emulator("webots", seed=1) as emu, ego.Robot(emu.path) as robot:
        assert isinstance(robot.channel, ChannelBase)
        with pytest.warns(DeprecatedNameWarning, match=r"Robot\.channel"):
            assert robot.link is robot.channel
        assert not hasattr(robot, "link_lock")  # the channel locks itself
