"""Hostile world files and floor textures are refused in bounded time and memory, with
one line naming the file and the reason; under ``ego run`` and ``ego demo`` that line is
the one ``ego: error:`` line (ISSUE 22 item 6).

Each world is loaded in a child process (tests/hostile_files.py measures it and kills it
at a timeout). Before the fix: 10^5 boxes took hundreds of MB and many seconds and ended
in a link timeout that never named the world; a 2 KB .wbt whose DEF/USE nodes double 40
times hung; a FIFO texture hung; a 12000x12000 PNG of 445 KB peaked near 2 GB; a texture
could be any file of the machine; NaN, inf and 1e300 were taken as sizes and points;
2000-deep nesting was a RecursionError naming no file.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from helpers import ego_command
from hostile_files import make, png, python, run_bounded, textured_world

PEAK_MB = 200
WALL_S = 20
TIMEOUT_S = 60

LOAD_WORLD = """
import sys
from firmware_sim.worlds import load_world
try:
    load_world(sys.argv[1])
except Exception as exc:
    print(f"{type(exc).__name__}: {exc}", file=sys.stderr)
    sys.exit(3)
print("loaded")
"""

CONTROLLER = "from controller import Robot\nRobot()\n"


@pytest.fixture(scope="module")
def folder(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return tmp_path_factory.mktemp("hostile-worlds")


@pytest.mark.parametrize(
    ("name", "reason"),
    [
        ("many-boxes.toml", "1800000 bytes is over the 1 MiB bound for a TOML world"),
        ("2000-boxes.toml", "2000 [[box]] tables is over the bound of 100"),
        ("huge.toml", "314572800 bytes is over the 1 MiB bound for a TOML world"),
        ("deep.toml", "nested more than 16 deep"),
        ("nan-track.toml", "floor point [nan, 0.3] is not two numbers in -5..5 m"),
        ("huge-track.toml", "floor point [1e+300, 0.3] is not two numbers in -5..5 m"),
        ("many-boxes.wbt", "more than 100 boxes: over the bound for a world"),
        ("million-boxes.wbt", "14000022 bytes is over the 8 MiB bound for a Webots world"),
        ("deep.wbt", "nodes nested more than 64 deep (at a Group)"),
        ("unterminated.wbt", "unreadable text at offset 39"),
        ("many-tokens.wbt", "more than 500000 tokens: over the bound for a world"),
        ("nan-box.wbt", "WoodenBox.size nan 0.1 0.1: must each be finite numbers within"),
        ("inf-arena.wbt", "RectangleArena.floorSize inf 1: must each be finite numbers"),
        ("huge-box.wbt", "WoodenBox.translation 1e+300 0 0: must each be finite numbers"),
        ("huge-camera.wbt", "E-puck.camera_width 100000: must be a finite number within 1..640"),
        ("fifo-texture.wbt", "fifo.png: is a FIFO, not a regular file"),
        ("huge-texture.wbt", "huge.png: a floor image of 12000x12000 pixels is over the bound"),
        ("outside-texture.wbt", "the floor texture '../outside.png' is outside the world's "
                                "folder"),
    ],
)  # fmt: skip
def test_a_hostile_world_is_refused_in_one_line_within_budget(
    folder: Path, name: str, reason: str
) -> None:
    path = make(folder, name)
    done = run_bounded([*python(LOAD_WORLD), path], TIMEOUT_S)
    assert done.status is not None, f"{name}: still loading after {TIMEOUT_S} s (a hang)"
    assert done.status == 3, f"exit {done.status}: {done.stdout} {done.stderr[-2000:]}"
    assert len(done.lines) == 1 and len(done.lines[0]) < 400, done.stderr[-2000:]
    assert done.lines[0].startswith(f"ValueError: {path}: "), done.lines[0]
    assert reason in done.lines[0], done.lines[0]
    assert done.peak_mb < PEAK_MB, f"peak {done.peak_mb:.0f} MB"
    assert done.wall_s < WALL_S, f"{done.wall_s:.1f} s"


def test_a_node_used_twice_at_each_of_40_levels_is_walked_once(folder: Path) -> None:
    # The floor appearance reaches 2^41 nodes through DEF/USE, but holds 41.
    done = run_bounded([*python(LOAD_WORLD), make(folder, "def-use.wbt")], TIMEOUT_S)
    assert done.status == 0 and done.stdout.strip() == "loaded", done.stderr[-2000:]
    assert done.peak_mb < PEAK_MB and done.wall_s < WALL_S, (done.peak_mb, done.wall_s)


def test_a_floor_image_at_the_pixel_bound_loads_without_a_float64_copy(tmp_path: Path) -> None:
    # 4096x4096: its RGB is 48 MB; float64 copies of it made it 700 MB and more.
    png(tmp_path / "floor.png", 4096, 4096)
    world = textured_world(tmp_path / "big-floor.wbt", "floor.png")
    done = run_bounded([*python(LOAD_WORLD), str(world)], TIMEOUT_S)
    assert done.status == 0 and done.stdout.strip() == "loaded", done.stderr[-2000:]
    assert done.peak_mb < 400, f"peak {done.peak_mb:.0f} MB"


def _one_error_line(args: list[str], cwd: Path, reason: str) -> None:
    done = run_bounded([*ego_command(), *args], TIMEOUT_S, cwd=cwd)
    assert done.status is not None, f"ego {' '.join(args)}: still running after {TIMEOUT_S} s"
    assert done.status == 1, f"exit {done.status}: {done.stderr[-2000:]}"
    assert "Traceback" not in done.stderr, done.stderr[-2000:]
    assert len(done.lines) == 1, done.stderr[-2000:]
    assert done.lines[0].startswith("ego: error: ") and reason in done.lines[0], done.lines[0]
    assert done.peak_mb < PEAK_MB and done.wall_s < WALL_S, (done.peak_mb, done.wall_s)


@pytest.mark.parametrize(
    ("name", "reason"),
    [
        ("deep.wbt", "deep.wbt: nodes nested more than 64 deep"),
        ("many-boxes.wbt", "many-boxes.wbt: more than 100 boxes"),
        ("many-boxes.toml", "many-boxes.toml: 1800000 bytes is over the 1 MiB bound"),
        ("fifo-texture.wbt", "fifo.png: is a FIFO, not a regular file"),
        ("nan-box.wbt", "nan-box.wbt: WoodenBox.size nan 0.1 0.1: must each be finite"),
    ],
)
def test_ego_run_says_a_bad_world_in_one_error_line(folder: Path, name: str, reason: str) -> None:
    (folder / "ctrl.py").write_text(CONTROLLER)
    args = ["run", "--port", "sim", "--world", make(folder, name), "ctrl.py"]
    _one_error_line(args, folder, reason)


def test_ego_demo_says_a_bad_world_in_one_error_line(folder: Path) -> None:
    args = ["demo", "--no-dashboard", "--duration", "1", "--world", make(folder, "deep.toml")]
    _one_error_line(args, folder, "deep.toml: nested more than 16 deep")
