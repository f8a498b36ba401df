"""Closing a robot's parts one after another, none of whose failures is hidden."""

from __future__ import annotations

import logging
from collections.abc import Callable, Iterable

from ego.errors import EgoError

__all__ = ["close_each"]


def close_each(name: str, closers: Iterable[Callable[[], None]], log: logging.Logger) -> None:
    """Run every closer of the robot called ``name``, each even if one before it failed.

    Closers stop the robot (their batch sets the wheels to 0) and release it: a failure is
    logged at WARNING with the robot's name, so that an unconfirmed stop is never hidden.
    An error that is neither ego's nor the system's (a bug) is raised again once every
    closer has run.
    """
    bug: Exception | None = None
    for close in closers:
        try:
            close()
        except (EgoError, OSError) as exc:
            log.warning("%s: could not stop and close it: %s", name, exc)
        except Exception as exc:
            log.warning("%s: could not stop and close it: %r", name, exc)
            bug = bug or exc
    if bug is not None:
        raise bug
