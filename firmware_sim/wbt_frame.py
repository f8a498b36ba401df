"""A Webots world file's frame read from its nodes (firmware_sim.frame): the coordinate
system its WorldInfo declares (an NUE world converted to ENU in place, as Webots R2022a
converts it) and where its RectangleArena stands; and the poses the file gives carried
into the arena's frame, where the emulator simulates."""

from __future__ import annotations

import re
from dataclasses import replace

from firmware_sim.frame import ENU, NUE, Frame, to_enu
from firmware_sim.markers import Marker
from firmware_sim.wbt_node import Node
from firmware_sim.wbt_solids import yaw
from firmware_sim.world import Block, Lamp, Pose

__all__ = ["carry", "read_frame"]


def read_frame(version: str, nodes: list[Node]) -> Frame:
    """The file's frame; an NUE file's nodes are converted to ENU on the way."""
    system = _system(version, nodes)
    if system == NUE:
        to_enu(nodes)
    for node in reversed(nodes):  # the last arena, as world_from_wbt reads it
        if node.type == "RectangleArena":
            if system == NUE:
                _no_texture(node)
            x, y, _ = node.numbers("translation", 3, (0.0, 0.0, 0.0))
            rotation = node.numbers("rotation", 4, (0.0, 0.0, 1.0, 0.0))
            return Frame(x, y, yaw(rotation, "RectangleArena.rotation"), system)
    return Frame(system=system)


def _no_texture(arena: Node) -> None:
    """Refuse an NUE arena's floor image: how an old Floor laid its texture on the x-z
    plane is not modelled, and a line-follower's sensors would read it turned."""
    appearance = arena.fields.get("floorAppearance")
    for sub in appearance.walk() if isinstance(appearance, Node) else ():
        if sub.type == "ImageTexture" and sub.fields.get("url"):
            raise ValueError("RectangleArena.floorAppearance: a floor image in an NUE world "
                             "is not modelled (its orientation on the old x-z floor); open "
                             "and save the world once in Webots R2022a or newer")  # fmt: skip


def _system(version: str, nodes: list[Node]) -> str:
    """WorldInfo's coordinateSystem: NUE by default before R2022a, ENU since."""
    before = _before_r2022a(version)
    system = NUE if before else ENU
    for node in nodes:
        if node.type == "WorldInfo" and "coordinateSystem" in node.fields:
            given = node.fields["coordinateSystem"]
            system = given[0] if isinstance(given, list) and given else given
    if system == ENU and before:
        raise ValueError(f"a {version} world declared ENU keeps its objects in the old "
                         "axes (x right, y up, z back); open and save it once in Webots "
                         "R2022a or newer, which converts them")  # fmt: skip
    if system not in (ENU, NUE):
        raise ValueError(f"WorldInfo.coordinateSystem {system!r}: the emulator reads ENU "
                         "worlds (x east, y north, z up, Webots' since R2022a) and NUE ones "
                         "(x north, y up, z east, converted as Webots converts them)")  # fmt: skip
    return system


def _before_r2022a(version: str) -> bool:
    match = re.fullmatch(r"R(\d{4})([ab])(?:-.*)?", version)
    return match is not None and (int(match.group(1)), match.group(2)) < (2022, "a")


def carry(
    frame: Frame, blocks: list[Block], starts: list[Pose], markers: list[Marker], lamp: Lamp | None
) -> tuple[list[Block], list[Pose], list[Marker], Lamp | None]:
    """The world's solids, robots and lamp, given in the file's (ENU) frame, in the
    arena's: the emulator's."""
    if frame.x_m == 0 and frame.y_m == 0 and frame.yaw_rad == 0:
        return blocks, starts, markers, lamp
    moved_blocks = []
    for b in blocks:
        x, y, turn = frame.into_arena(b.x_m, b.y_m, b.yaw_rad)
        moved_blocks.append(replace(b, x_m=x, y_m=y, yaw_rad=turn))
    moved_starts = [Pose(*frame.into_arena(p.x_m, p.y_m, p.theta_rad)) for p in starts]
    moved_markers = []
    for m in markers:
        x, y, turn = frame.into_arena(m.x_m, m.y_m, m.yaw_rad)
        moved_markers.append(replace(m, x_m=x, y_m=y, yaw_rad=turn))
    if lamp is not None:
        x, y, _ = frame.into_arena(lamp.x_m, lamp.y_m, 0.0)
        lamp = replace(lamp, x_m=x, y_m=y)
    return moved_blocks, moved_starts, moved_markers, lamp
