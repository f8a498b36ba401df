"""One node of a Webots world file as :mod:`firmware_sim.wbt` parses it."""

from __future__ import annotations

import math
from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import Any

__all__ = ["MAX_LENGTH_M", "Node"]

#: Every length and position, in metres, is within +-this.
MAX_LENGTH_M = 100.0


@dataclass
class Node:
    """One node of the file: its type, its DEF name, and its fields as parsed values."""

    type: str
    fields: dict[str, Any] = field(default_factory=dict)
    name: str | None = None

    def numbers(
        self,
        key: str,
        count: int,
        default: tuple[float, ...],
        low: float = -MAX_LENGTH_M,
        high: float = MAX_LENGTH_M,
    ) -> tuple[float, ...]:
        """The field ``key``: ``count`` finite numbers within ``low..high``."""
        value = self.fields.get(key)
        if value is None:
            return default
        if (
            not isinstance(value, list)
            or len(value) != count
            or not all(isinstance(v, int | float) and not isinstance(v, bool) for v in value)
        ):
            raise ValueError(f"{self.type}.{key} must be {count} numbers, not {value!r}"[:200])
        if not all(math.isfinite(v) and low <= v <= high for v in value):
            each = "must be a finite number" if count == 1 else "must each be finite numbers"
            raise ValueError(f"{self.type}.{key} {' '.join(map(str, value))}: {each} within "
                             f"{low:g}..{high:g}")  # fmt: skip
        return tuple(float(v) for v in value)

    def walk(self) -> Iterator[Node]:
        """This node and every node below it, each once (a USE is its DEF's node, so a
        file that USEs a node twice at each of 40 levels still has 41 nodes to visit)."""
        seen: set[int] = set()
        stack = [self]
        while stack:
            node = stack.pop()
            if id(node) in seen:
                continue
            seen.add(id(node))
            yield node
            children: list[Node] = []
            for value in node.fields.values():
                children.extend(i for i in (value if isinstance(value, list) else [value])
                                if isinstance(i, Node))  # fmt: skip
            stack.extend(reversed(children))
