"""A queryable served by a thread of ours: Zenoh's own threads never run Python.

A query waits in a bounded ring inside Zenoh (:data:`RING_CAPACITY`; when it is full,
Zenoh drops the oldest, and its querier's ``get`` times out) until the intake's thread
takes it and hands it to ``handle``. So a flood on one key neither holds Zenoh's
network threads on Python's GIL (where they would delay every other message, the
controller's batches included) nor queues without end; and the thread offers the GIL
after each query, so that its refusal loop does not hold the other threads of the node.
"""

from __future__ import annotations

import logging
import time
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from ego.nursery import Nursery

if TYPE_CHECKING:
    import zenoh

__all__ = ["RING_CAPACITY", "Intake"]

log = logging.getLogger(__name__)

#: How many queries a key keeps waiting for its thread.
RING_CAPACITY = 256


class Intake:
    """Declares a queryable on ``key`` and runs ``handle(query)`` for each, in one thread
    of ``nursery``."""

    def __init__(
        self,
        session: zenoh.Session,
        key: str,
        handle: Callable[[Any], None],
        nursery: Nursery,
        *,
        capacity: int = RING_CAPACITY,
    ) -> None:
        import zenoh

        self.key = key
        self.handle = handle
        self.queryable = session.declare_queryable(key, zenoh.handlers.RingChannel(capacity))
        # The handler, not the queryable: undeclaring the queryable while its own recv()
        # waits would fail ("Already borrowed"); the handler's recv ends when it closes.
        self._queries = self.queryable.handler
        nursery.start_thread(self._run, name=f"ego-zenoh {key}")

    def _run(self) -> None:
        while True:
            try:
                query = self._queries.recv()
            except Exception as exc:  # zenoh.ZError: the queryable is undeclared
                log.debug("%s: no more queries (%s)", self.key, exc)
                return
            try:
                self.handle(query)
            except Exception:  # a bug: logged with its traceback; the key stays served
                log.exception("%s: a query failed", self.key)
            # Zenoh ends a query (its querier gets the replies, consolidated) when the query
            # is dropped: let go of it now, not when the next one arrives. A queued query is
            # held, and dropped, by its job.
            del query
            # Under a flood this thread always has work: offer the GIL after each query,
            # so that the controller's batches and the deadman's timer (threads of this
            # process too) never wait a whole switch interval behind a refusal loop.
            time.sleep(0)

    def undeclare(self) -> None:
        """Stop taking queries; the thread ends once the one in hand is handled (its
        nursery, the node's, joins it)."""
        self.queryable.undeclare()
