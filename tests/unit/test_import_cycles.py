"""No import circles: no module of ego imports one that imports it back, directly or round a loop.

Every import counts, at module level, inside functions and under ``TYPE_CHECKING`` alike:
a circle hidden in a function still means neither module can be read without the other.
An import names the module it loads (``from ego.core import robot`` names ``ego.core.robot``;
``from ego.core.robot import Robot`` names ``ego.core.robot``); a package's ``__init__`` run on
the way is not counted, so a registry may import its backends lazily.
"""

from __future__ import annotations

import ast
from collections.abc import Iterator, Mapping
from pathlib import Path

import ego

#: Where ego is installed: the checkout's src, or on a board the wheel's site-packages.
SOURCE = Path(ego.__file__).resolve().parents[1]


def module_files(root: Path = SOURCE) -> dict[str, Path]:
    """Every module under ``root``/ego by dotted name (a package by its own name)."""
    found = {}
    for path in sorted((root / "ego").rglob("*.py")):
        parts = path.relative_to(root).with_suffix("").parts
        if parts[-1] == "__init__":
            parts = parts[:-1]
        found[".".join(parts)] = path
    return found


def _imported(node: ast.AST, here: str, is_package: bool) -> Iterator[str]:
    if isinstance(node, ast.Import):
        yield from (alias.name for alias in node.names)
    elif isinstance(node, ast.ImportFrom):
        base = node.module or ""
        if node.level:
            package = here.split(".") if is_package else here.split(".")[:-1]
            package = package[: len(package) - (node.level - 1)]
            base = ".".join([*package, base] if base else package)
        for alias in node.names:
            yield f"{base}.{alias.name}"
            yield base


def import_graph(modules: Mapping[str, Path]) -> dict[str, set[str]]:
    """Module -> the ego modules it imports, anywhere in its body."""
    graph: dict[str, set[str]] = {}
    for name, path in modules.items():
        targets: set[str] = set()
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for node in ast.walk(tree):
            names = list(_imported(node, name, path.name == "__init__.py"))
            # "from ego.x import y": y if it is a module, else ego.x itself.
            submodules = [n for n in names[0::2] if n in modules]
            if isinstance(node, ast.ImportFrom):
                targets.update(submodules or [n for n in names[1::2] if n in modules])
            else:
                targets.update(n for n in names if n in modules)
        targets.discard(name)
        graph[name] = targets
    return graph


def circles(graph: Mapping[str, set[str]]) -> list[list[str]]:
    """The strongly connected groups of more than one module (Tarjan, iterative)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    found: list[list[str]] = []
    for start in graph:
        if start in index:
            continue
        work = [(start, iter(sorted(graph[start])))]
        index[start] = low[start] = len(index)
        stack.append(start)
        on_stack.add(start)
        while work:
            node, edges = work[-1]
            for target in edges:
                if target not in index:
                    index[target] = low[target] = len(index)
                    stack.append(target)
                    on_stack.add(target)
                    work.append((target, iter(sorted(graph[target]))))
                    break
                if target in on_stack:
                    low[node] = min(low[node], index[target])
            else:
                work.pop()
                if work:
                    low[work[-1][0]] = min(low[work[-1][0]], low[node])
                if low[node] == index[node]:
                    group = []
                    while True:
                        member = stack.pop()
                        on_stack.discard(member)
                        group.append(member)
                        if member == node:
                            break
                    if len(group) > 1:
                        found.append(sorted(group))
    return found


def test_ego_has_no_import_circle() -> None:
    found = circles(import_graph(module_files()))
    assert not found, "import circles: " + "; ".join(" <-> ".join(group) for group in found)


def _package(tmp_path: Path, files: Mapping[str, str]) -> dict[str, Path]:
    for relative, text in files.items():
        path = tmp_path / "ego" / relative
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text, encoding="utf-8")
    return module_files(tmp_path)


def test_a_circle_through_a_function_or_type_checking_is_found(tmp_path: Path) -> None:
    modules = _package(tmp_path, {
        "__init__.py": "",
        "a.py": "def f():\n    from ego.b import g\n",
        "b.py": "from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from ego import c\n",
        "c.py": "import ego.a\n",
        "d.py": "from ego import a\n",
    })
    assert circles(import_graph(modules)) == [["ego.a", "ego.b", "ego.c"]]


def test_relative_imports_and_lazy_registries(tmp_path: Path) -> None:
    modules = _package(tmp_path, {
        "__init__.py": "",
        "pkg/__init__.py": "def load():\n    from . import impl\n",
        "pkg/base.py": "X = 1\n",
        "pkg/impl.py": "from .base import X\n",
        "loop/__init__.py": "",
        "loop/one.py": "from .two import Y\n",
        "loop/two.py": "from ego.loop.one import Z\n",
    })
    graph = import_graph(modules)
    assert graph["ego.pkg"] == {"ego.pkg.impl"}
    assert graph["ego.pkg.impl"] == {"ego.pkg.base"}
    assert circles(graph) == [["ego.loop.one", "ego.loop.two"]]
