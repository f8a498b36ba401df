"""A Griffe extension for the API reference: ego's docstrings, written in the reST habits
of the standard library (doctest examples, ``:class:`` roles, ``::`` literal blocks), made
into the Markdown that mkdocstrings renders.

Without it a doctest's ``>>>`` would render as nested block quotes and a role as its raw
text. The docstrings themselves stay as they are: ``help()`` and doctest read them.
"""

from __future__ import annotations

import re
from typing import Any

import griffe

#: ``:class:`~ego.seam.channel.Channel``` and the like: the role's target, as code.
_ROLE = re.compile(r":(?:py:)?(?:mod|class|func|meth|attr|data|exc|obj):`~?([^`]+)`")
_PROMPT = re.compile(r"^(\s*)(>>>|\.\.\.)( |$)")
_SKIP = re.compile(r"\s*# doctest: \+SKIP\s*$")


def _role(match: re.Match[str]) -> str:
    target = match.group(1)
    shown = target.rsplit(".", 1)[-1] if match.group(0).count("~") else target
    return f"`{shown}`"


def _fence_doctests(lines: list[str]) -> list[str]:
    """Each run of ``>>>``/``...`` lines becomes a fenced Python block, prompts removed."""
    out: list[str] = []
    block: list[str] = []
    indent = ""
    for line in [*lines, ""]:
        prompt = _PROMPT.match(line)
        if prompt and (block or prompt.group(2) == ">>>"):
            indent = indent if block else prompt.group(1)
            block.append(_SKIP.sub("", line[prompt.end() :]))
            continue
        if block:
            out += ["", f"{indent}```python", *(f"{indent}{b}" for b in block), f"{indent}```", ""]
            block = []
        out.append(line)
    return out[:-1]


def to_markdown(docstring: str) -> str:
    """ego's reST-flavoured docstring as Markdown (see the module's docstring)."""
    text = _ROLE.sub(_role, docstring)
    # "...like this::" then an indented block: Markdown shows the block as code already.
    text = re.sub(r"(?<=\S)::$", ":", text, flags=re.M)
    text = re.sub(r"^\s*::$", "", text, flags=re.M)
    return "\n".join(_fence_doctests(text.splitlines()))


class RestToMarkdown(griffe.Extension):
    """Rewrite every docstring of the loaded objects to Markdown."""

    def on_instance(self, *, obj: griffe.Object, **kwargs: Any) -> None:
        if obj.docstring is not None:
            obj.docstring.value = to_markdown(obj.docstring.value)
