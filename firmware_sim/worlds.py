"""World files for the emulator: TOML, by path or by the name of a built-in world.

A world file describes what the emulated e-puck lives in::

    [arena]
    size_m = 1.0                      # a square arena of this side, walled

    [robot]                           # where the robot starts
    x_m = 0.0
    y_m = -0.3
    heading_deg = 0.0

    [floor]                           # "marks" (a stripe and a disc) or a line track
    kind = "track"
    width_m = 0.02
    points = [[-0.3, -0.3], [0.3, -0.3], [0.3, 0.3], [-0.3, 0.3]]

    [[box]]                           # as many as wanted
    x_m = 0.2
    y_m = 0.1
    size_m = 0.08
    rgb = [200, 30, 30]
    name = "TARGET"                   # optional: a Supervisor's getFromDef("TARGET")

    [lamp]                            # the light the light sensors see
    x_m = 0.3
    y_m = 0.3
    height_m = 0.15

    [sound]                           # what the microphones hear
    x_m = -0.3
    y_m = 0.3
    frequency_hz = 1000.0

    [wheels]                          # how the wheels slip, how noisy their counters are
    slip = 0.01                       # mean fraction of the turning lost (0..0.5)
    encoder_noise_steps = 1.0         # counter error after one wheel turn (0..100 steps)

    devices = ["gps", "compass", "touch sensor"]   # ground truth, emulator only (top level)

    [robot] camera_width = 52, camera_height = 39  # the size Webots controllers get

    [[robots]]                        # more robots of a swarm (ego swarm), after [robot]
    x_m = 0.1
    y_m = 0.0
    heading_deg = 180

Built in, by name: ``arena`` (the default), ``line-track``, ``maze``, ``light``. A file
with a key it does not know, or a value of the wrong kind, is refused with ValueError
naming the file and the key. A Webots world file (``.wbt``) is read too, for the part
the emulator models (firmware_sim.wbt); what it skips is logged.

Bounds (docs/bad_input.md): a TOML world is a regular file of at most
:data:`MAX_TOML_BYTES`, nested at most :data:`MAX_DEPTH` deep, with at most
:data:`MAX_BOXES` boxes, :data:`MAX_ROBOTS` robots and :data:`MAX_TRACK_POINTS` track
points; every number is finite and within its key's range.
"""

from __future__ import annotations

import logging
import math
import sys
from importlib import resources
from pathlib import Path
from typing import Any

if sys.version_info >= (3, 11):
    import tomllib
else:  # Python 3.10: the same parser, published before it joined the standard library
    import tomli as tomllib

from firmware_sim.files import read_regular
from firmware_sim.floor import LineTrack, Marks
from firmware_sim.wbt import MAX_BOXES, MAX_ROBOTS, world_from_wbt
from firmware_sim.wheels import MAX_ENCODER_NOISE_STEPS, MAX_SLIP, WheelModel
from firmware_sim.world import Arena, Block, Lamp, Pose, SoundSource, World

__all__ = [
    "BUILT_IN",
    "MAX_BOXES",
    "MAX_DEPTH",
    "MAX_ROBOTS",
    "MAX_TOML_BYTES",
    "MAX_TRACK_POINTS",
    "load_world",
    "world_names",
]

#: A TOML world file's size, at most (the built-in worlds are under 1 KB).
MAX_TOML_BYTES = 1 << 20
#: Tables and arrays nest at most this deep (a world needs 3: floor.points).
MAX_DEPTH = 16
#: A line track's points, at most.
MAX_TRACK_POINTS = 10_000

log = logging.getLogger(__name__)
#: Nodes of a Webots world that only change how Webots draws it: skipped quietly.
_COSMETIC = frozenset(
    {"WorldInfo", "Viewpoint", "TexturedBackground", "TexturedBackgroundLight",
     "Background", "DirectionalLight"}
)  # fmt: skip

#: The worlds shipped with the emulator (firmware_sim/worlds/NAME.toml).
BUILT_IN = ("arena", "line-track", "maze", "light")
_DEVICES = frozenset({"gps", "compass", "touch sensor"})
_TABLES = {
    "arena": {"size_m"},
    "robot": {"x_m", "y_m", "heading_deg", "camera_width", "camera_height"},
    "floor": {"kind", "width_m", "points", "closed"},
    "box": {"x_m", "y_m", "size_m", "rgb", "name"},
    "lamp": {"x_m", "y_m", "height_m"},
    "sound": {"x_m", "y_m", "frequency_hz", "amplitude"},
    "wheels": {"slip", "encoder_noise_steps"},
}


def world_names() -> tuple[str, ...]:
    return BUILT_IN


def load_world(spec: str | Path, seed: int | None = None) -> World:
    """The World a file (or a built-in world's name) describes."""
    if isinstance(spec, str) and spec in BUILT_IN:
        text = resources.files("firmware_sim").joinpath(f"worlds/{spec}.toml").read_text()
        where = f"built-in world {spec!r}"
    else:
        path = Path(spec)
        if not path.is_file():
            raise ValueError(
                f"world {str(spec)!r} is neither a file nor one of {', '.join(BUILT_IN)}"
            )
        if path.suffix == ".wbt":
            return _webots_world(path, seed)
        text, where = _read_toml(path), str(path)
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ValueError(f"{where}: not TOML: {exc}") from exc
    except RecursionError as exc:  # tomllib recurses once a level, ~300 levels at most
        raise ValueError(f"{where}: nested more than {MAX_DEPTH} deep") from exc
    _check_depth(data, where)
    return _build(data, where, seed)


def _read_toml(path: Path) -> str:
    try:
        return read_regular(path, MAX_TOML_BYTES, "a TOML world").decode("utf-8")
    except UnicodeDecodeError as exc:
        raise ValueError(f"{path}: byte {exc.start} is not UTF-8 text") from exc


def _check_depth(data: Any, where: str) -> None:
    """Refuse tables and arrays nested deeper than MAX_DEPTH (walked without recursion)."""
    stack: list[tuple[Any, int]] = [(data, 1)]
    while stack:
        value, depth = stack.pop()
        if depth > MAX_DEPTH:
            raise ValueError(f"{where}: nested more than {MAX_DEPTH} deep")
        items = value.values() if isinstance(value, dict) else value
        stack.extend((v, depth + 1) for v in items if isinstance(v, dict | list))


def _webots_world(path: Path, seed: int | None) -> World:
    read = world_from_wbt(path, seed)
    for note in read.notes:
        cosmetic = note.rsplit(" ", 1)[-1] in _COSMETIC
        log.log(logging.INFO if cosmetic else logging.WARNING, "%s: %s", path.name, note)
    return read.world


def _build(data: dict[str, Any], where: str, seed: int | None) -> World:
    unknown = set(data) - {*_TABLES, "devices", "name", "robots"}
    if unknown:
        raise ValueError(f"{where}: unknown key {sorted(unknown)[0]!r}")
    tables = {
        name: _table(data, name, where)
        for name in ("arena", "robot", "floor", "lamp", "sound", "wheels")
    }
    boxes = data.get("box", [])
    if not isinstance(boxes, list):
        raise ValueError(f"{where}: [[box]] must be an array of tables")
    _at_most(boxes, MAX_BOXES, "[[box]] tables", where)
    _at_most(data.get("robots", []), MAX_ROBOTS - 1, "[[robots]] tables", where)
    arena = Arena(half_size_m=_number(tables["arena"], "size_m", where, 1.0, 0.2, 10.0) / 2)
    robot = tables["robot"]
    start = Pose(
        _number(robot, "x_m", where, 0.0, -5.0, 5.0),
        _number(robot, "y_m", where, 0.0, -5.0, 5.0),
        math.radians(_number(robot, "heading_deg", where, 0.0, -360.0, 360.0)),
    )
    blocks = [_box(box, where) for box in boxes]
    robots = data.get("robots", [])
    if not isinstance(robots, list) or not all(isinstance(r, dict) for r in robots):
        raise ValueError(f"{where}: [[robots]] must be an array of tables")
    for extra in robots:
        unknown_keys = set(extra) - {"x_m", "y_m", "heading_deg"}
        if unknown_keys:
            raise ValueError(f"{where}: unknown key {sorted(unknown_keys)[0]!r} in [[robots]]")
    starts = [start] + [
        Pose(_number(r, "x_m", where, 0.0, -5.0, 5.0), _number(r, "y_m", where, 0.0, -5.0, 5.0),
             math.radians(_number(r, "heading_deg", where, 0.0, -360.0, 360.0)))
        for r in robots
    ]  # fmt: skip
    lamp = tables["lamp"]
    sound = tables["sound"]
    devices = data.get("devices", [])
    if not isinstance(devices, list) or not set(devices) <= _DEVICES:
        raise ValueError(f"{where}: devices must be some of {', '.join(sorted(_DEVICES))}")
    return World(
        seed=seed,
        arena=arena,
        blocks=blocks if "box" in data else None,
        lamp=Lamp(
            _number(lamp, "x_m", where, 0.3, -5, 5),
            _number(lamp, "y_m", where, 0.3, -5, 5),
            _number(lamp, "height_m", where, 0.15, 0.0, 5.0),
        ),
        sound=SoundSource(
            _number(sound, "x_m", where, -0.3, -5, 5),
            _number(sound, "y_m", where, 0.3, -5, 5),
            _number(sound, "frequency_hz", where, 1000.0, 10.0, 8000.0),
            _number(sound, "amplitude", where, 900.0, 0.0, 2047.0),
        ),
        start=start,
        floor=_floor(tables["floor"], where),
        devices=frozenset(devices),
        camera_size=_camera_size(robot, where),
        starts=starts,
        wheels=_wheels(tables["wheels"], where),
    )


def _wheels(table: dict[str, Any], where: str) -> WheelModel:
    default = WheelModel()
    slip = _number(table, "slip", where, default.slip, 0.0, MAX_SLIP)
    noise = _number(table, "encoder_noise_steps", where, default.encoder_noise_steps, 0.0,
                    MAX_ENCODER_NOISE_STEPS)  # fmt: skip
    return WheelModel(slip, noise)


def _camera_size(robot: dict[str, Any], where: str) -> tuple[int, int] | None:
    if "camera_width" not in robot and "camera_height" not in robot:
        return None
    size = robot.get("camera_width", 52), robot.get("camera_height", 39)
    if not all(isinstance(v, int) and not isinstance(v, bool) and 1 <= v <= 640 for v in size):
        raise ValueError(f"{where}: camera_width/camera_height must be whole pixels 1..640")
    return size[0], size[1]


def _at_most(items: Any, bound: int, what: str, where: str) -> None:
    if isinstance(items, list) and len(items) > bound:
        raise ValueError(f"{where}: {len(items)} {what} is over the bound of {bound}")


def _table(data: dict[str, Any], name: str, where: str) -> dict[str, Any]:
    table = data.get(name, {})
    if not isinstance(table, dict):
        raise ValueError(f"{where}: [{name}] must be a table")
    unknown = set(table) - _TABLES[name]
    if unknown:
        raise ValueError(f"{where}: unknown key {sorted(unknown)[0]!r} in [{name}]")
    return table


def _number(table: dict[str, Any], key: str, where: str, default: float, low: float,
            high: float) -> float:  # fmt: skip
    value = table.get(key, default)
    if isinstance(value, bool) or not isinstance(value, int | float) or not low <= value <= high:
        raise ValueError(f"{where}: {key} = {value!r} is not a number in {low}..{high}")
    return float(value)


def _box(box: Any, where: str) -> Block:
    if not isinstance(box, dict):
        raise ValueError(f"{where}: each [[box]] must be a table")
    unknown = set(box) - _TABLES["box"]
    if unknown:
        raise ValueError(f"{where}: unknown key {sorted(unknown)[0]!r} in [[box]]")
    rgb = box.get("rgb", [160, 120, 80])
    if not (
        isinstance(rgb, list)
        and len(rgb) == 3
        and all(isinstance(c, int) and 0 <= c <= 255 for c in rgb)
    ):
        raise ValueError(f"{where}: a box's rgb must be three integers 0..255, not {rgb!r}")
    return Block(
        _number(box, "x_m", where, 0.0, -5, 5),
        _number(box, "y_m", where, 0.0, -5, 5),
        _number(box, "size_m", where, 0.08, 0.01, 2.0) / 2,
        (rgb[0], rgb[1], rgb[2]),
        name=_name(box, where),
    )


def _name(box: dict[str, Any], where: str) -> str | None:
    """A box's ``name``: a Supervisor's ``getFromDef`` finds it by it, as a DEF name."""
    name = box.get("name")
    if name is not None and not (isinstance(name, str) and name.isidentifier()):
        raise ValueError(f"{where}: a box's name must be an identifier, not {name!r}")
    return name


def _floor(table: dict[str, Any], where: str) -> Marks | LineTrack:
    kind = table.get("kind", "marks")
    if kind == "marks":
        return Marks()
    if kind != "track":
        raise ValueError(f"{where}: floor kind {kind!r} is not marks or track")
    points = table.get("points")
    _at_most(points, MAX_TRACK_POINTS, "floor points", where)
    if not (isinstance(points, list) and all(
        isinstance(p, list) and len(p) == 2 and all(isinstance(v, int | float) for v in p)
        for p in points
    )):  # fmt: skip
        raise ValueError(f"{where}: floor points must be a list of [x, y] pairs")
    for point in points:
        if not all(not isinstance(v, bool) and -5 <= v <= 5 for v in point):  # NaN fails too
            raise ValueError(f"{where}: floor point {point!r} is not two numbers in -5..5 m")
    try:
        return LineTrack(
            tuple((float(x), float(y)) for x, y in points),
            _number(table, "width_m", where, 0.02, 0.001, 0.2),
            bool(table.get("closed", True)),
        )
    except ValueError as exc:
        raise ValueError(f"{where}: {exc}") from exc
