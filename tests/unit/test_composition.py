"""The Robot and the Camera are composed of objects handed their collaborators: no class
body stubs out what a host class provides (issue 35, "mixins that only work by MRO order")."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

import ego
import firmware_sim
from ego.core.robot_devices import FamilyAttribute
from ego.devices.proximity import ProximitySensors

ROOT = Path(ego.__file__).resolve().parent
SIM = Path(firmware_sim.__file__).resolve().parent


def _stubs(path: Path) -> list[str]:
    """Methods whose whole body (after a docstring) is ``raise NotImplementedError``."""
    found = []
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if not isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            continue
        body = node.body
        if body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant):
            body = body[1:]
        if len(body) == 1 and isinstance(body[0], ast.Raise):
            raised = body[0].exc
            if isinstance(raised, ast.Call):
                raised = raised.func
            if isinstance(raised, ast.Name) and raised.id == "NotImplementedError":
                found.append(f"{path.name}:{node.lineno} {node.name}")
    return found


def test_no_method_is_a_stub_for_what_a_host_class_provides() -> None:
    stubs = [s for tree in (ROOT, SIM) for p in sorted(tree.rglob("*.py")) for s in _stubs(p)]
    assert stubs == []


def test_the_stub_finder_finds_a_stub(tmp_path: Path) -> None:
    module = tmp_path / "mixin.py"
    module.write_text('class M:\n    def hook(self) -> None:\n        """Doc."""\n'
                      "        raise NotImplementedError\n")  # fmt: skip
    assert _stubs(module) == ["mixin.py:2 hook"]


def test_a_family_attribute_is_named_as_its_class_declares() -> None:
    class Host:
        proximity = FamilyAttribute(ProximitySensors)

    with pytest.raises(TypeError, match=r"Host\.sonar holds the family 'proximity'"):
        FamilyAttribute(ProximitySensors).__set_name__(Host, "sonar")

