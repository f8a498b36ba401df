"""A task group for the servers' event loops: every task it starts is awaited or cancelled
by :meth:`Nursery.aclose`, so none outlives the server that started it.

asyncio's own ``TaskGroup`` (3.11) ends the group when one task fails and cannot take
tasks once it is closing; a server wants neither (one bad request must not take it
down, and a late event after close is dropped), and ego still runs on 3.10.
"""

from __future__ import annotations

import asyncio
import logging
from collections.abc import Coroutine
from typing import Any

__all__ = ["Nursery"]

log = logging.getLogger(__name__)


class Nursery:
    """Owns the tasks it starts: a failing one is logged, :meth:`aclose` ends the rest."""

    def __init__(self, name: str) -> None:
        self.name = name
        self._tasks: set[asyncio.Task[None]] = set()
        self._closed = False

    def __len__(self) -> int:
        return len(self._tasks)

    def start_soon(self, work: Coroutine[Any, Any, None]) -> None:
        """Run ``work`` as a task of this nursery (on the running loop); once the nursery
        is closing, ``work`` is closed unrun."""
        if self._closed:
            work.close()
            return
        task = asyncio.get_running_loop().create_task(work)
        self._tasks.add(task)
        task.add_done_callback(self._finished)

    def _finished(self, task: asyncio.Task[None]) -> None:
        self._tasks.discard(task)
        if not task.cancelled() and task.exception() is not None:
            log.error("%s: a task failed", self.name, exc_info=task.exception())

    async def aclose(self) -> None:
        """Take no more tasks, cancel the running ones and wait until all have ended."""
        self._closed = True
        while self._tasks:
            tasks = list(self._tasks)
            for task in tasks:
                task.cancel()
            await asyncio.gather(*tasks, return_exceptions=True)
