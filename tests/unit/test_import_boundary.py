"""The library and the emulator stay apart: each is a check on the other only so.

ego never imports ``firmware_sim`` (the ``sim`` backend is found through the
``ego.backends`` entry point), and ``firmware_sim`` never imports ``ego`` except in
``ego_backend.py``, the adapter that entry point names. Checked on the source itself,
with ``ast``, so that a lazy import inside a function is caught too.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
LIBRARY = sorted((ROOT / "src" / "ego").rglob("*.py"))
EMULATOR = sorted((ROOT / "firmware_sim").rglob("*.py"))
#: The one emulator module that may import ego: the backend adapter.
ADAPTER = ROOT / "firmware_sim" / "ego_backend.py"


def imported_packages(path: Path) -> set[str]:
    """The top-level package of every import in ``path``, wherever it sits in the file."""
    found: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"), str(path))):
        if isinstance(node, ast.Import):
            found |= {alias.name.split(".")[0] for alias in node.names}
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            found.add(node.module.split(".")[0])
    return found


def test_the_walk_sees_both_trees() -> None:
    assert len(LIBRARY) > 30 and len(EMULATOR) > 5 and ADAPTER in EMULATOR


@pytest.mark.parametrize("path", LIBRARY, ids=lambda p: str(p.relative_to(ROOT)))
def test_the_library_never_imports_the_emulator(path: Path) -> None:
    assert "firmware_sim" not in imported_packages(path)


@pytest.mark.parametrize(
    "path", [p for p in EMULATOR if p != ADAPTER], ids=lambda p: str(p.relative_to(ROOT))
)
def test_the_emulator_never_imports_the_library(path: Path) -> None:
    assert "ego" not in imported_packages(path)


def test_the_checker_catches_a_lazy_import(tmp_path: Path) -> None:
    sample = tmp_path / "sample.py"
    sample.write_text("def f():\n    from firmware_sim.camera import X\n    import ego.core\n")
    assert {"firmware_sim", "ego"} <= imported_packages(sample)
