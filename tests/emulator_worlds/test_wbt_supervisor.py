"""A .wbt world's bodiless supervisor (``Robot { supervisor TRUE }``) and its robots' DEF
names, as ego swarm reads them (issue 36, item 4)."""

from __future__ import annotations

from pathlib import Path

import pytest

from firmware_sim.wbt import world_from_wbt
from firmware_sim.world import Pose

HEADER = "#VRML_SIM R2023b utf8\nRectangleArena { floorSize 1 1 }\n"
ROBOTS = "DEF A E-puck { translation -0.1 0 0 }\nE-puck { translation 0.1 0 0 }\n"


def _world(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "w.wbt"
    path.write_text(HEADER + ROBOTS + text)
    return path


def test_a_supervisor_robot_is_read_with_its_controller_and_pose(tmp_path: Path) -> None:
    path = _world(tmp_path, 'DEF BOSS Robot { translation 0.2 0.3 0.1 rotation 0 0 1 1.5 '
                  'name "boss" controller "trainer" supervisor TRUE '
                  'children [ Emitter { } Receiver { } ] }\n')  # fmt: skip
    world = world_from_wbt(path).world
    (boss,) = world.supervisors
    assert (boss.name, boss.def_name, boss.controller) == ("boss", "BOSS", "trainer")
    assert boss.pose == Pose(0.2, 0.3, 1.5)
    assert world.robot_names == ["A", None]


def test_a_robot_that_is_no_supervisor_is_skipped(tmp_path: Path) -> None:
    read = world_from_wbt(_world(tmp_path, 'Robot { controller "x" }\n'))
    assert read.world.supervisors == []
    assert "skipped 1 Robot" in read.notes


def test_a_supervisor_without_a_controller_to_run_is_refused(tmp_path: Path) -> None:
    path = _world(tmp_path, 'DEF S Robot { controller "<extern>" supervisor TRUE }\n')
    with pytest.raises(ValueError, match=r"w\.wbt: Robot S supervisor TRUE: its controller"):
        world_from_wbt(path)


def test_the_radio_channels_come_from_the_file(tmp_path: Path) -> None:
    path = tmp_path / "w.wbt"
    path.write_text(HEADER + "E-puck { emitter_channel 2 }\nE-puck { receiver_channel 3 }\n"
                    'Robot { controller "t" supervisor TRUE children [ Emitter { channel 1 } '
                    "Receiver { } ] }\n"
                    'Robot { controller "u" supervisor TRUE }\n')  # fmt: skip
    world = world_from_wbt(path).world
    assert world.robot_radio == [(2, 1), (1, 3)]
    first, second = world.supervisors
    assert (first.emitter_channel, first.receiver_channel) == (1, 0)  # Webots' default 0
    assert (second.emitter_channel, second.receiver_channel) == (None, None)
