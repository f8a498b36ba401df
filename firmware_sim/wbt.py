"""Webots world files (``.wbt``) read for the part the emulator can model.

A ``.wbt`` file is VRML97-like text: nodes ``Type { field value ... }``, values that are
numbers, strings, ``TRUE``/``FALSE``, a node, or a ``[ ... ]`` list of either, with
``DEF``/``USE`` names and ``#`` comments. :func:`parse_wbt` turns it into plain
:class:`Node` trees; :func:`world_from_wbt` reads from them what the emulator models:

* ``RectangleArena``: ``floorSize`` (x, y), ``wallHeight``, ``floorTileSize``, and the
  floor texture where ``floorAppearance`` names an ``ImageTexture`` (read from beside the
  world file, as Webots does): the ground sensors and the camera then see that image;
* boxes: ``WoodenBox`` (``translation``, ``rotation``, ``size``) and any ``Solid`` whose
  children hold a ``Shape`` with ``Box`` geometry (its ``size``, and its colour from the
  appearance's ``baseColor`` or ``diffuseColor``);
* each ``E-puck``: ``translation`` and ``rotation`` (the start poses: a swarm's robots
  in order), and the first one's ``camera_width``/``camera_height`` fields (the camera
  size a Webots controller gets);
* a ``Robot`` with ``supervisor TRUE``: a bodiless supervisor (firmware_sim.wbt_supervisor)
  whose controller ``ego swarm`` runs beside the e-pucks; every E-puck's DEF name;
* a ``PointLight``'s ``location``: the lamp the light sensors see;
* any other ``Solid`` (``Transform``, ``Pose``, ``Group``) with a DEF name, whatever its
  shape (a flat marker, a Plane): its pose only (firmware_sim.markers), for a
  Supervisor's ``getFromDef``; nothing bumps into it or senses it.

Everything else (Viewpoint, backgrounds, other robots...) is skipped, each skipped node
type listed in :attr:`WbtWorld.notes`. A world declared ``coordinateSystem "NUE"`` (y
up; an R2021 file is NUE unless it says otherwise) is converted to ENU as Webots R2022a
converts it, and a ``RectangleArena`` may stand off the origin and turn about the
vertical: the emulator simulates in the arena's own frame and a Supervisor answers in the
file's (firmware_sim.frame, firmware_sim.wbt_frame). A GPS or Compass in the first
E-puck's ``turretSlot`` or ``groundSensorsSlot`` is a ground-truth device mounted where
the slot is (firmware_sim.wbt_slots). A box may turn about the vertical or lie on a face
(a rotation that swaps its axes, as Webots' converter writes it): it stands on the floor
with its sides swapped; one on an edge or a corner, a robot or an arena rotated about
anything but the vertical are refused naming the node and field: the emulator's world is
flat.

Bounds (docs/bad_input.md): a file of at most :data:`MAX_WBT_BYTES`, at most
:data:`MAX_NODES` nodes nested at most :data:`MAX_DEPTH` deep and :data:`MAX_TOKENS`
tokens, at most :data:`MAX_BOXES` boxes, :data:`MAX_ROBOTS` e-pucks and 8 supervisor
Robots (firmware_sim.wbt_supervisor.MAX_SUPERVISORS); every number finite,
lengths and positions within +-:data:`MAX_LENGTH_M` m; a floor texture inside the
world's folder (see firmware_sim.floor for its own bounds). A ``USE`` is the node its
``DEF`` made, not a copy: a walk meets each node once.
"""

from __future__ import annotations

import re
from collections import deque
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from firmware_sim.files import read_regular
from firmware_sim.floor import ImageFloor, Plain
from firmware_sim.frame import Frame
from firmware_sim.markers import Marker
from firmware_sim.wbt_frame import carry, read_frame
from firmware_sim.wbt_node import MAX_LENGTH_M, Node
from firmware_sim.wbt_slots import slot_devices
from firmware_sim.wbt_solids import MARKER_TYPES, block, box_shape, marker, yaw
from firmware_sim.wbt_supervisor import MAX_SUPERVISORS, Bodiless, bodiless, epuck_channels
from firmware_sim.world import Arena, Block, Lamp, Pose, World

__all__ = [
    "MAX_BOXES",
    "MAX_DEPTH",
    "MAX_LENGTH_M",
    "MAX_NODES",
    "MAX_ROBOTS",
    "MAX_TOKENS",
    "MAX_WBT_BYTES",
    "Node",
    "WbtWorld",
    "parse_wbt",
    "world_from_wbt",
]

#: A .wbt file's size, at most (Webots' own worlds are tens of KB).
MAX_WBT_BYTES = 8 << 20
#: Nodes in a file, at most, and how deep they nest.
MAX_NODES = 100_000
MAX_DEPTH = 64
#: Tokens (names, values, brackets) in a file, at most: a few seconds of parsing.
MAX_TOKENS = 500_000
#: Boxes (WoodenBox, Solid boxes) and e-pucks a world may hold. The emulator traces each
#: proximity ray against every box in Python: past ~100 boxes a step's sensors no longer
#: come back within the link's reply time (the built-in maze has 4).
MAX_BOXES = 100
MAX_ROBOTS = 100

# A string is matched as runs of plain characters between escapes ("unrolled"): an
# alternation repeated per character kept a backtracking record per character, 1 GB for
# an unterminated 8 MB string.
_TOKEN = re.compile(
    r'\s*(?:#[^\n]*|("[^"\\]*(?:\\.[^"\\]*)*")|([\[\]{}])|([^\s\[\]{}"#]+))', re.DOTALL
)
_LITERALS = {"TRUE": True, "FALSE": False}


def _tokens(text: str) -> Iterator[str]:
    """The file's tokens, one at a time (a list of them all would be ten times the text)."""
    pos = count = 0
    while pos < len(text):
        match = _TOKEN.match(text, pos)
        if match is None or match.end() == pos:
            if text[pos : pos + 4096].strip():
                raise ValueError(f"unreadable text at offset {pos}: {text[pos : pos + 20]!r}")
            break
        pos = match.end()
        token = match.group(1) or match.group(2) or match.group(3)
        if token:
            count += 1
            if count > MAX_TOKENS:
                raise ValueError(f"more than {MAX_TOKENS} tokens: over the bound for a world")
            yield token


class _Parser:
    def __init__(self, text: str) -> None:
        self._tokens = _tokens(text)
        self._ahead: deque[str] = deque()
        self.defs: dict[str, Node] = {}
        self.depth = 0
        self.nodes = 0

    def peek(self, ahead: int = 0) -> str | None:
        while len(self._ahead) <= ahead:
            token = next(self._tokens, None)
            if token is None:
                return None
            self._ahead.append(token)
        return self._ahead[ahead]

    def take(self) -> str:
        token = self.peek()
        if token is None:
            raise ValueError("the file ends inside a node")
        self._ahead.popleft()
        return token

    def count_node(self) -> None:
        self.nodes += 1
        if self.nodes > MAX_NODES:
            raise ValueError(f"more than {MAX_NODES} nodes: over the bound for a world")

    def at_node(self) -> bool:
        token = self.peek()
        return token in ("DEF", "USE") or (
            token is not None and self.peek(1) == "{" and _is_name(token)
        )

    def node(self) -> Node:
        token = self.take()
        if token == "USE":
            used = self.take()
            if used not in self.defs:
                raise ValueError(f"USE {used} before its DEF")
            return self.defs[used]
        name: str | None = None
        if token == "DEF":
            name, token = self.take(), self.take()
        if self.take() != "{":
            raise ValueError(f"{token} is not followed by {{")
        self.count_node()
        if self.depth >= MAX_DEPTH:
            raise ValueError(f"nodes nested more than {MAX_DEPTH} deep (at a {token})")
        self.depth += 1
        node = Node(token, name=name)
        while (key := self.take()) != "}":
            if not _is_name(key):
                raise ValueError(f"in {token}: {key!r} is not a field name")
            node.fields[key] = self.value()
        self.depth -= 1
        if name is not None:
            self.defs[name] = node
        return node

    def value(self) -> Any:
        if self.peek() == "[":
            self.take()
            items: list[Any] = []
            while self.peek() != "]":
                if self.peek() is None:
                    raise ValueError("the file ends inside [ ]")
                items.append(self.node() if self.at_node() else _scalar(self.take()))
            self.take()
            return items
        if self.at_node():
            return self.node()
        if self.peek() == "NULL":
            self.take()
            return None
        values = []
        while (token := self.peek()) is not None and _is_scalar(token):
            values.append(_scalar(self.take()))
        return values


_NAME = re.compile(r"[A-Za-z_][\w\-]*")
_INTEGER = re.compile(r"[+-]?(0x[0-9a-fA-F]+|\d+)")


def _is_name(token: str) -> bool:
    return _NAME.fullmatch(token) is not None and token not in _LITERALS


def _is_scalar(token: str) -> bool:
    return token.startswith('"') or token in _LITERALS or _number(token) is not None


def _number(token: str) -> float | int | None:
    try:
        return int(token, 0) if _INTEGER.fullmatch(token) else float(token)
    except ValueError:
        return None


def _scalar(token: str) -> Any:
    if token.startswith('"'):
        return bytes(token[1:-1], "utf-8").decode("unicode_escape")
    if token in _LITERALS:
        return _LITERALS[token]
    number = _number(token)
    if number is None:
        raise ValueError(f"{token!r} is not a value")
    return number


def parse_wbt(text: str) -> tuple[str, list[Node]]:
    """The file's header version (``R2023b``; ``""`` if none) and its top-level nodes."""
    header = re.match(r"#VRML_SIM\s+(\S+)", text)
    parser = _Parser(text)
    nodes: list[Node] = []
    while (token := parser.peek()) is not None:
        if token in ("EXTERNPROTO", "IMPORTABLE"):
            parser.take()
            if token == "IMPORTABLE":
                parser.take()  # EXTERNPROTO
            parser.take()  # its URL
            continue
        nodes.append(parser.node())
    return (header.group(1) if header else ""), nodes


@dataclass
class WbtWorld:
    """What :func:`world_from_wbt` made of a file: the World, and the notes on what it
    skipped."""

    world: World
    notes: list[str]


def world_from_wbt(path: Path, seed: int | None = None) -> WbtWorld:
    """The emulator's World for a Webots world file (the subset in this module's doc)."""
    where = str(path)
    nodes, frame = _read_nodes(path)
    arena, floor = Arena(), None
    blocks: list[Block] = []
    starts: list[Pose] = []
    camera_size: tuple[int, int] | None = None
    lamp: Lamp | None = None
    robot_name: str | None = None
    skipped: dict[str, int] = {}
    markers: list[Marker] = []
    mounts: dict[str, tuple[float, float, float]] = {}
    slot_notes: list[str] = []
    robot_names: list[str | None] = []
    radio: list[tuple[int, int]] = []
    supervisors: list[Bodiless] = []
    try:
        for node in nodes:
            if node.type == "WorldInfo":
                pass  # its coordinateSystem: read_frame's
            elif node.type == "RectangleArena":
                arena, floor = _arena(node, path.parent)
            elif node.type == "WoodenBox":
                size = node.numbers("size", 3, (0.6, 0.6, 0.6))
                blocks.append(block(node, size, (150, 110, 60)))
            elif node.type == "Solid" and (shape := box_shape(node)) is not None:
                blocks.append(block(node, *shape))
            elif node.type == "E-puck":
                starts.append(_pose(node))
                robot_names.append(node.name)
                radio.append(epuck_channels(node))
                if len(starts) == 1:
                    robot_name = node.name
                    camera_size = _camera_size(node)
                    mounts, slot_notes = slot_devices(node)
            elif node.type == "PointLight" and lamp is None:
                x, y, z = node.numbers("location", 3, (0.0, 0.0, 0.0))
                lamp = Lamp(x, y, max(z, 0.0))
            elif (supervisor := bodiless(node)) is not None:
                supervisors.append(supervisor)
            elif node.name and node.type in MARKER_TYPES:
                markers.append(marker(node))
            else:
                skipped[node.type] = skipped.get(node.type, 0) + 1
            _within_bounds(blocks, starts)
            if len(supervisors) > MAX_SUPERVISORS:
                raise ValueError(f"more than {MAX_SUPERVISORS} supervisor Robots")
    except ValueError as exc:
        raise ValueError(f"{where}: {exc}") from exc
    blocks, starts, markers, lamp = carry(frame, blocks, starts, markers, lamp)
    notes = [f"skipped {count} {kind}" for kind, count in sorted(skipped.items())] + slot_notes
    if not starts:
        notes.append("no E-puck in the world: the robot starts at the origin")
    world = World(
        seed=seed,
        arena=arena,
        blocks=blocks,
        lamp=lamp,
        start=starts[0] if starts else None,
        floor=floor or Plain(),
        camera_size=camera_size,
        starts=starts,
        devices=frozenset(mounts),
    )
    world.robot_name, world.markers = robot_name, markers
    world.frame, world.mounts = frame, mounts
    world.robot_names, world.robot_radio = robot_names, radio
    world.supervisors = supervisors
    return WbtWorld(world, notes)


def _read_nodes(path: Path) -> tuple[list[Node], Frame]:
    """The top-level nodes of the world file at ``path``, in ENU (an NUE world
    converted), and its frame (firmware_sim.wbt_frame)."""
    where = str(path)
    try:
        text = read_regular(path, MAX_WBT_BYTES, "a Webots world").decode("utf-8")
    except UnicodeDecodeError as exc:
        raise ValueError(f"{where}: byte {exc.start} is not UTF-8 text") from exc
    except OSError as exc:
        raise ValueError(f"{where}: {exc.strerror or exc}") from exc
    try:
        version, nodes = parse_wbt(text)
        return nodes, read_frame(version, nodes)
    except ValueError as exc:
        raise ValueError(f"{where}: {exc}") from exc


def _within_bounds(blocks: list[Block], starts: list[Pose]) -> None:
    if len(blocks) > MAX_BOXES:
        raise ValueError(f"more than {MAX_BOXES} boxes: over the bound for a world")
    if len(starts) > MAX_ROBOTS:
        raise ValueError(f"more than {MAX_ROBOTS} E-pucks: over the bound for a world")


def _arena(node: Node, folder: Path) -> tuple[Arena, ImageFloor | Plain]:
    """The arena in its own frame (where it stands: firmware_sim.wbt_frame)."""
    sx, sy = node.numbers("floorSize", 2, (1.0, 1.0))
    tile_x, tile_y = node.numbers("floorTileSize", 2, (0.5, 0.5))
    tile = (tile_x, tile_y)
    height = node.numbers("wallHeight", 1, (0.1,))[0]
    if min(sx, sy, tile[0], tile[1], height) <= 0:
        raise ValueError("RectangleArena sizes must be positive")
    arena = Arena(half_size_m=sx / 2, half_y_m=sy / 2, wall_height_m=height)
    appearance = node.fields.get("floorAppearance")
    for sub in appearance.walk() if isinstance(appearance, Node) else ():
        urls = sub.fields.get("url") if sub.type == "ImageTexture" else None
        if urls:
            return arena, ImageFloor.from_file(_texture(folder, urls[0]), (sx, sy), tile)
    return arena, Plain()


def _texture(folder: Path, url: object) -> Path:
    """The floor texture's file, which must be in the world's folder or below it (as a
    Webots project keeps its textures): a world names no other file of the machine."""
    image = (folder / str(url)).resolve()
    if not image.is_relative_to(folder.resolve()):
        raise ValueError(f"the floor texture {str(url)!r} is outside the world's folder "
                         f"{str(folder)!r}: textures are read from beside the world")  # fmt: skip
    return image


def _pose(node: Node) -> Pose:
    """The robot's start pose: in an ENU world the e-puck's front is its own +x."""
    x, y, _ = node.numbers("translation", 3, (0.0, 0.0, 0.0))
    return Pose(x, y, yaw(node.numbers("rotation", 4, (0.0, 0.0, 1.0, 0.0)), "E-puck"))


def _camera_size(node: Node) -> tuple[int, int] | None:
    if "camera_width" not in node.fields and "camera_height" not in node.fields:
        return None
    # As a TOML world's: the rendered image is width x height, so bounded like it.
    width = node.numbers("camera_width", 1, (52.0,), 1, 640)[0]
    height = node.numbers("camera_height", 1, (39.0,), 1, 640)[0]
    if not (width.is_integer() and height.is_integer() and min(width, height) >= 1):
        raise ValueError(f"E-puck camera size {width}x{height} is not whole pixels")
    return int(width), int(height)
