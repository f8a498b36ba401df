"""A swarm's scene (firmware_sim.swarm_scene) asked through the Zenoh scene codec
(ego.zenoh_net.scene_codec), without a network: the robots by name, a box moved in every
robot's world, the reset, and the codec's errors."""

from __future__ import annotations

import pytest

from ego.errors import ProtocolError
from ego.zenoh_net.scene_codec import answer, request, result
from firmware_sim.swarm_scene import SwarmScene
from firmware_sim.world import Block, Pose, World


def _worlds() -> list[World]:
    box = Block(0.3, 0.3, 0.02, (200, 0, 0), name="BOX")
    worlds = [World(seed=i, blocks=[box]) for i in range(3)]
    for world, x in zip(worlds, (-0.2, 0.2, 0.0), strict=True):
        world.start_at(Pose(x, 0.0, 0.0))
    return worlds


def _ask(scene: SwarmScene, op: str, name: str = "", *args: float) -> object:
    return result(answer(scene, request(op, name, *args)), "test")


def test_each_member_sees_the_others_by_name_and_itself_as_robot() -> None:
    worlds = _worlds()
    scenes = [SwarmScene(worlds, ["A", "B", "BOSS"], me, bodiless=1) for me in range(3)]
    assert _ask(scenes[0], "names") == ["A", "B", "BOSS", "BOX"]
    assert _ask(scenes[1], "pose", "A")[:2] == [-0.2, 0.0]  # type: ignore[index]
    assert _ask(scenes[1], "pose", "")[:2] == [0.2, 0.0]  # type: ignore[index]
    assert _ask(scenes[0], "robot_name") == "A"
    assert [_ask(scenes[0], "kind", n) for n in ("B", "BOSS", "BOX")] == ["E-puck", "Robot",
                                                                           "Solid"]  # fmt: skip


def test_a_box_moved_moves_in_every_world_and_the_reset_puts_it_back() -> None:
    worlds = _worlds()
    scene = SwarmScene(worlds, ["A", "B", "BOSS"], 2, bodiless=1)
    _ask(scene, "set_pose", "BOX", 0.1, -0.3, 0.0, 0.5)
    assert [(w.blocks[0].x_m, w.blocks[0].y_m) for w in worlds] == [(0.1, -0.3)] * 3
    _ask(scene, "set_pose", "B", 0.0, 0.25, 0.0, 0.0)
    worlds[0].set_speeds(300, 300)
    worlds[2].set_speeds(200, 200)
    _ask(scene, "reset")
    assert [(w.blocks[0].x_m, w.blocks[0].y_m) for w in worlds] == [(0.3, 0.3)] * 3
    assert (worlds[1].snapshot().x_m, worlds[1].snapshot().y_m) == (0.2, 0.0)
    # The asking member's robot stands still; another keeps what its controller set.
    assert worlds[2].speeds == (0, 0) and worlds[0].speeds == (300, 300)


def test_an_unknown_solid_is_a_key_error_and_a_bad_request_a_protocol_error() -> None:
    scene = SwarmScene(_worlds(), ["A", "B", "BOSS"], 0, bodiless=1)
    with pytest.raises(KeyError, match="no solid named 'NOPE'"):
        _ask(scene, "pose", "NOPE")
    with pytest.raises(ProtocolError, match="op is one of"):
        result(answer(scene, b'{"op": "delete"}'), "test")
    with pytest.raises(ProtocolError, match="takes 4 finite numbers"):
        result(answer(scene, request("set_pose", "A", 1.0)), "test")
    with pytest.raises(ProtocolError, match="not JSON"):
        result(answer(scene, b"\xff"), "test")


def test_a_bodiless_supervisors_node_is_named_by_its_name_field_unless_taken() -> None:
    from ego.app.swarm import _node_name

    assert _node_name("trainer", 0, ["epuck0", "epuck1"]) == "trainer"
    assert _node_name("robot", 1, ["epuck0", "robot"]) == "supervisor1"  # a second "robot"
    assert _node_name("epuck0", 0, ["epuck0"]) == "supervisor0"
    assert _node_name("my robot(1)", 2, []) == "supervisor2"  # not a Zenoh name
