"""No module over 500 lines (issue 35, the house style): small modules with one job.

Every ``.py`` file under ``src/ego``, ``firmware_sim``, ``benchmarks`` and ``tests`` is
counted as ``wc -l`` counts it; the failure lists each one over the limit, largest first.
"""

from __future__ import annotations

from pathlib import Path

from helpers import needs_source_tree

#: It counts the repository's trees, which a board (an installed wheel) does not have.
pytestmark = needs_source_tree
ROOT = Path(__file__).resolve().parents[2]
TREES = ("src/ego", "firmware_sim", "benchmarks", "tests")
LIMIT = 500


def line_counts() -> dict[str, int]:
    """Each module's path (relative to the repository, with /) and its number of lines."""
    counts = {}
    for tree in TREES:
        for path in sorted((ROOT / tree).rglob("*.py")):
            counts[path.relative_to(ROOT).as_posix()] = path.read_bytes().count(b"\n")
    return counts


def test_the_trees_are_found_and_counted() -> None:
    counts = line_counts()
    for tree in TREES:
        assert any(name.startswith(tree + "/") for name in counts), f"no module under {tree}"
    assert counts["src/ego/errors.py"] > 0


def test_no_module_is_over_500_lines() -> None:
    over = {name: n for name, n in line_counts().items() if n > LIMIT}
    listing = "\n".join(f"  {n:5d} {name}" for name, n in sorted(over.items(), key=lambda i: -i[1]))
    assert not over, f"modules over {LIMIT} lines (split them by job):\n{listing}"
