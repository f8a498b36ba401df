"""The layers are a contract, and the suite fails when it is broken.

``pyproject.toml`` states them for import-linter (``[tool.importlinter]``): ego's layers,
imports running downward only, and the emulator apart from the library but for its one
bridge, ``firmware_sim/ego_backend.py``. Here ``lint-imports`` checks the tree, then a
copy of it with one wrong import added, to show that each kind of violation is caught:
a lazy upward import inside a function, ego importing the emulator, and the emulator
importing ego outside its bridge.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from helpers import needs_source_tree

ROOT = Path(__file__).resolve().parents[2]
LINT_IMPORTS = Path(sys.executable).with_name("lint-imports")
pytestmark = [
    needs_source_tree,
    pytest.mark.skipif(
        not LINT_IMPORTS.exists(),
        reason="lint-imports (import-linter, the dev extra) is not installed",
    ),
]


def lint_imports(root: Path) -> subprocess.CompletedProcess[str]:
    """``lint-imports`` on the tree at ``root`` (its pyproject.toml, its packages first)."""
    env = {**os.environ, "PYTHONPATH": f"{root / 'src'}{os.pathsep}{root}"}
    return subprocess.run(
        [str(LINT_IMPORTS), "--no-cache", "--config", str(root / "pyproject.toml")],
        cwd=root, env=env, capture_output=True, text=True, timeout=120, check=False,
    )  # fmt: skip


def test_the_tree_keeps_every_contract() -> None:
    result = lint_imports(ROOT)
    assert result.returncode == 0, result.stdout + result.stderr
    assert "Contracts: 3 kept, 0 broken." in result.stdout


def copy_tree(into: Path) -> Path:
    """The packages and the configuration, copied (no caches, no virtual environment)."""
    ignore = shutil.ignore_patterns("__pycache__", "*.pyc")
    shutil.copytree(ROOT / "src" / "ego", into / "src" / "ego", ignore=ignore)
    shutil.copytree(ROOT / "firmware_sim", into / "firmware_sim", ignore=ignore)
    shutil.copy(ROOT / "pyproject.toml", into / "pyproject.toml")
    return into


@pytest.mark.parametrize(
    ("module", "added", "broken"),
    [
        # A lazy import inside a function counts: the seam reaching up to the app.
        ("src/ego/seam/validate.py", "def _f() -> None:\n    from ego.app import cli\n",
         "ego's layers: imports run downward only BROKEN"),
        # The core picking a concrete backend (what open_group did).
        ("src/ego/core/group.py", "from ego.backends import zenoh_remote\n",
         "ego's layers: imports run downward only BROKEN"),
        ("src/ego/core/ports.py", "import firmware_sim.world\n",
         "ego never imports the emulator BROKEN"),
        ("firmware_sim/world.py", "from ego.errors import EgoError\n",
         "the emulator imports ego only through its adapter, the one bridge BROKEN"),
    ],
    ids=["lazy-upward-import", "core-picks-a-backend", "ego-imports-emulator",
         "emulator-imports-ego"],
)  # fmt: skip
def test_a_wrong_import_is_caught(tmp_path: Path, module: str, added: str, broken: str) -> None:
    root = copy_tree(tmp_path)
    with (root / module).open("a", encoding="utf-8") as f:
        f.write("\n" + added)
    result = lint_imports(root)
    assert result.returncode == 1, result.stdout + result.stderr
    assert broken in result.stdout
