"""MkDocs hooks: the CLI reference page from the ego command's parser, and a link check.

The CLI page cannot drift from the command: every subcommand's ``--help`` text as
``ego SUBCOMMAND --help`` prints it, generated at build time. The pages are written to
be read on the repository too, so they link to files outside docs/ (the README, the
examples, the benchmarks' results): MkDocs cannot follow those, so this hook checks
that every relative link names a file that exists, and warns (an error under
``--strict``) for one that does not.
"""

from __future__ import annotations

import argparse
import logging
import os
import re
from pathlib import Path
from typing import Any

log = logging.getLogger("mkdocs.hooks.ego")

#: A Markdown link's target: ``[text](target)`` or ``[text](target#anchor)``.
_LINK = re.compile(r"\]\(([^()\s#]+)(?:#[^()\s]*)?\)")

CLI_PAGE = "guide/api/cli.md"

INTRO = """# The `ego` command

Generated from the command's own parser at build time: each section is what
`ego COMMAND --help` prints. Installed with the package (`pip install 'ego[pc]'`, or
`pip install -e '.[pc]'` in a checkout); `python -m ego` is the same command.
"""


def _subparsers(parser: argparse.ArgumentParser) -> dict[str, argparse.ArgumentParser]:
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            return dict(action.choices)
    return {}


def cli_reference() -> str:
    """The page: the top-level help, then each subcommand's."""
    from ego.app.cli import build_parser

    os.environ["COLUMNS"] = "100"  # argparse wraps to the terminal; a page has none
    parser = build_parser()
    parts = [INTRO, "```text", parser.format_help().rstrip(), "```"]
    for name, sub in _subparsers(parser).items():
        parts += [f"\n## `ego {name}`\n", "```text", sub.format_help().rstrip(), "```"]
    return "\n".join(parts) + "\n"


def broken_links(markdown: str, source: Path) -> list[str]:
    """The relative link targets in ``markdown`` that name no file beside ``source``."""
    broken = []
    for match in _LINK.finditer(markdown):
        target = match.group(1)
        if "://" in target or target.startswith(("mailto:", "/")):
            continue
        if not (source.parent / target).exists():
            broken.append(target)
    return broken


def on_page_markdown(markdown: str, page: Any, **_: Any) -> str:
    if page.file.src_uri == CLI_PAGE:
        return cli_reference()
    for target in broken_links(markdown, Path(page.file.abs_src_path)):
        log.warning("%s links to %s, which does not exist", page.file.src_uri, target)
    return markdown
