"""The error tree (one ego.errors): what a caller catches is what real calls raise.

The tree is declared once, by the classes; the drawing in the module's docstring must
match them (the docs stay true), and each promise of the tree is checked on a real call:
a builtin handler (``except ValueError``, ``except TimeoutError``...) catches the ego
error a call raises, and its message carries the values.
"""

from __future__ import annotations

import ast
import re
from collections.abc import Iterator
from pathlib import Path

import pytest
from fakes import FAST_LINK
from helpers import world_of

import ego
import firmware_sim
from ego import errors
from ego.seam.batch import Request
from ego.seam.profile import Command
from ego.serial.link import Link
from ego.serial.protocol import encode_batch
from ego.serial.transport import SerialTransport
from firmware_sim import Emulator, FaultTimings

_LINE = re.compile(r"^(?P<indent>[ │├└─]*)(?P<name>[A-Z]\w+)(?: \((?P<mixins>[\w, ]+)\))?")


def _drawn() -> dict[str, tuple[str | None, set[str]]]:
    """Each class in the docstring's drawing: (its parent there, the builtins it names)."""
    assert errors.__doc__ is not None
    drawing = errors.__doc__.split("::", 1)[1]
    drawn: dict[str, tuple[str | None, set[str]]] = {}
    stack: list[tuple[int, str]] = []
    for line in drawing.splitlines():
        match = _LINE.match(line.strip("\n"))
        if match is None or not line.strip():
            continue
        depth = len(match["indent"])
        while stack and stack[-1][0] >= depth:
            stack.pop()
        mixins = {m.strip() for m in (match["mixins"] or "").split(",") if m.strip()}
        drawn[match["name"]] = (stack[-1][1] if stack else None, mixins)
        stack.append((depth, match["name"]))
    return drawn


def test_the_drawing_in_the_docstring_is_the_tree_the_classes_declare() -> None:
    drawn = _drawn()
    declared = {name for name in errors.__all__ if name != "ControllerError"}
    assert set(drawn) == declared, set(drawn) ^ declared
    for name, (parent, mixins) in drawn.items():
        cls = getattr(errors, name)
        ego_bases = [b.__name__ for b in cls.__mro__[1:] if b.__module__ == errors.__name__
                     and not b.__name__.startswith("_")]  # fmt: skip
        assert (ego_bases[0] if ego_bases else None) == parent, name
        for builtin in mixins:
            refined = getattr(errors, builtin, None) or __builtins__[builtin]  # type: ignore[index]
            assert issubclass(cls, refined), f"{name} is drawn as a {builtin}"


@pytest.fixture
def robot() -> Iterator[ego.Robot]:
    with ego.Robot("sim", seed=1) as robot:
        yield robot


def test_a_missing_port_is_a_file_not_found(tmp_path: Path) -> None:
    missing = tmp_path / "ttyNONE"
    with pytest.raises(FileNotFoundError, match="ttyNONE") as caught:
        ego.Robot(str(missing))
    assert isinstance(caught.value, errors.PortNotFoundError)


def test_a_speed_out_of_range_is_a_value_error_that_names_it(robot: ego.Robot) -> None:
    with pytest.raises(ValueError, match="1200") as caught:
        robot.motors.set_speed(1200, 0)
    assert isinstance(caught.value, errors.OutOfRangeError)
    assert world_of(robot).speeds == (0, 0)  # refused, not clamped and sent


def test_an_unknown_device_is_a_key_error_listing_the_names_unquoted(robot: ego.Robot) -> None:
    with pytest.raises(KeyError) as caught:
        robot.device("ps12")
    assert isinstance(caught.value, errors.UnknownDeviceError)
    message = str(caught.value)
    assert message.startswith("no device named 'ps12'") and "ps7" in message


def test_a_robot_that_does_not_answer_is_a_timeout_error() -> None:
    with Emulator("webots", seed=1, timings=FaultTimings(stall_s=3.0)) as emu:
        link = Link(SerialTransport(emu.path), settings=FAST_LINK)
        try:
            emu.inject("stall", batch=emu.batches + 1)  # hung past every retry
            with pytest.raises(TimeoutError, match="reply bytes") as caught:
                link.exchange(encode_batch([Request(Command.PROXIMITY)], link.profile))
        finally:
            link.close()
    assert isinstance(caught.value, errors.LinkTimeoutError)
    assert isinstance(caught.value, OSError)  # a LinkError: except OSError catches it too


def _raised_names() -> set[str]:
    """Every name ego (or its emulator) makes an error of, ``X(...)``, or warns with,
    ``warn(message, X)``, outside ego.errors itself."""
    roots = (Path(errors.__file__).parent, Path(firmware_sim.__file__).parent)
    names: set[str] = set()
    for path in (p for root in roots for p in root.rglob("*.py")):
        if path == Path(errors.__file__):
            continue
        for node in ast.walk(ast.parse(path.read_text())):
            if not isinstance(node, ast.Call):
                continue
            named = [node.func]
            if getattr(node.func, "attr", getattr(node.func, "id", "")) == "warn":
                named += node.args[1:2]
            for name in named:
                if isinstance(name, ast.Name):
                    names.add(name.id)
                elif isinstance(name, ast.Attribute):
                    names.add(name.attr)
    return names


def test_every_leaf_of_the_tree_is_raised_somewhere() -> None:
    classes = [getattr(errors, name) for name in errors.__all__]
    leaves = {
        c.__name__ for c in classes if not any(o is not c and issubclass(o, c) for o in classes)
    }
    assert sorted(leaves - _raised_names()) == []
