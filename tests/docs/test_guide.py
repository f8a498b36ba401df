"""The guide (docs/guide/) and the examples' README cannot drift from the code: every
``ego`` command they show parses with ego's own command line, every example they name
exists, every relative link resolves, and the API reference's CLI page covers every
subcommand."""

from __future__ import annotations

import importlib.util
import os
import pwd
import re
import shlex
import shutil
import subprocess
import sys
from pathlib import Path
from types import ModuleType

import pytest

from ego.app.cli import build_parser

ROOT = Path(__file__).resolve().parents[2]
GUIDE = ROOT / "docs" / "guide"
PAGES = [*sorted(GUIDE.glob("*.md")), *sorted((GUIDE / "api").glob("*.md"))]
SHOWN = [*sorted(GUIDE.glob("*.md")), ROOT / "examples" / "README.md"]

#: A fenced code block of shell commands or of a systemd unit.
_BLOCK = re.compile(r"^```(sh|ini)\n(.*?)^```", re.M | re.S)
#: ``NAME=value`` before a command.
_ASSIGNMENT = re.compile(r"^[A-Z_]+=\S*$")


def hooks() -> ModuleType:
    """docs/guide/hooks.py, the MkDocs hook module, loaded as MkDocs loads it."""
    spec = importlib.util.spec_from_file_location("ego_docs_hooks", GUIDE / "hooks.py")
    assert spec and spec.loader
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def commands(text: str) -> list[list[str]]:
    """Every command line in the text's ``sh`` and ``ini`` blocks, as words, with the
    environment assignments before it and the comment after it left out."""
    found = []
    for _, block in _BLOCK.findall(text):
        for line in block.splitlines():
            line = line.removeprefix("ExecStart=")
            words = shlex.split(line, comments=True)
            while words and _ASSIGNMENT.match(words[0]):
                words.pop(0)
            if words and words[-1] == "&":
                words.pop()
            if words:
                found.append(words)
    return found


def ego_commands() -> list[tuple[str, list[str]]]:
    return [
        (f"{page.relative_to(ROOT)}: {shlex.join(words)}", words[1:])
        for page in SHOWN
        for words in commands(page.read_text(encoding="utf-8"))
        if Path(words[0]).name == "ego"
    ]


@pytest.mark.parametrize(("where", "args"), ego_commands(), ids=lambda v: str(v)[:90])
def test_every_ego_command_shown_parses(where: str, args: list[str]) -> None:
    try:
        build_parser().parse_args(args)
    except SystemExit as exc:  # argparse refuses (2), or --version/--help ends (0)
        assert exc.code == 0, f"{where}: ego refuses these arguments"


def test_the_guide_shows_ego_commands_of_every_kind() -> None:
    shown = {args[0] for _, args in ego_commands() if args}
    assert {"run", "serve", "secret", "swarm", "--version"} <= shown, shown


def test_every_example_the_guide_runs_exists() -> None:
    named = {
        word
        for page in SHOWN
        for words in commands(page.read_text(encoding="utf-8"))
        for word in words
        if word.startswith("examples/")
    }
    assert named, "the guide runs no example"
    for path in named:
        assert (ROOT / path).is_file(), path


@pytest.mark.parametrize("page", [*PAGES, ROOT / "examples" / "README.md"], ids=lambda p: p.name)
def test_every_relative_link_resolves(page: Path) -> None:
    assert hooks().broken_links(page.read_text(encoding="utf-8"), page) == []


def test_a_broken_link_is_found() -> None:
    text = "[a](nope.md) [b](index.md#road) [c](https://example.org/x.md) [d](../../README.md)"
    assert hooks().broken_links(text, GUIDE / "index.md") == ["nope.md"]


def test_the_cli_page_has_every_subcommand_with_its_options() -> None:
    page = hooks().cli_reference()
    for name in ("demo", "run", "sim", "serve", "secret", "replay", "swarm", "plot", "bench"):
        assert f"## `ego {name}`" in page, name
    assert "--supervised" in page and "--secret-file" in page


def test_the_readme_leads_to_the_guide_and_the_examples() -> None:
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    assert "(docs/guide/index.md)" in readme
    assert "(examples/README.md)" in readme
    for example in sorted((ROOT / "examples").glob("*.py")):
        assert f"examples/{example.name}" in readme, example.name


def test_docstrings_become_markdown_for_the_api_reference() -> None:
    pytest.importorskip("griffe", reason="the API reference needs the docs extra")
    spec = importlib.util.spec_from_file_location("ego_griffe_rest", GUIDE / "griffe_rest.py")
    assert spec and spec.loader
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    docstring = (
        "Steps through a :class:`~ego.seam.channel.Channel` (:mod:`ego.backends`).\n"
        "\n"
        ">>> import ego\n"
        '>>> with ego.Robot("sim") as robot:                  # doctest: +SKIP\n'
        "...     robot.step(64)\n"
        "\n"
        "The tree::\n"
        "\n"
        "    EgoError\n"
    )
    assert module.to_markdown(docstring) == (
        "Steps through a `Channel` (`ego.backends`).\n"
        "\n"
        "\n"
        "```python\n"
        "import ego\n"
        'with ego.Robot("sim") as robot:\n'
        "    robot.step(64)\n"
        "```\n"
        "\n"
        "\n"
        "The tree:\n"
        "\n"
        "    EgoError"
    )


def test_the_boot_service_is_a_unit_systemd_accepts(tmp_path: Path) -> None:
    """The Overo page's unit, with its paths pointed at this machine's, passes
    ``systemd-analyze verify`` without a word (an unknown key or value is reported)."""
    analyze = shutil.which("systemd-analyze")
    if analyze is None:
        pytest.skip("systemd-analyze is not installed here")
    (unit,) = re.findall(r"^```ini\n(.*?)^```", (GUIDE / "overo.md").read_text(), re.M | re.S)
    ego = Path(sys.executable).with_name("ego")
    (tmp_path / "obstacle_avoidance.py").write_text("")
    unit = unit.replace("/home/epuck/ego/bin/ego", str(ego)).replace("/home/epuck", str(tmp_path))
    unit = unit.replace("User=epuck", f"User={pwd.getpwuid(os.getuid()).pw_name}")
    path = tmp_path / "epuck-controller.service"
    path.write_text(unit)
    done = subprocess.run(
        [analyze, "verify", str(path)], capture_output=True, text=True, timeout=60, check=False
    )
    assert done.returncode == 0 and done.stderr.strip() == "", done.stderr
