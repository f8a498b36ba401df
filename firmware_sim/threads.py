"""The emulator's threads have owners: an :class:`OwnedThread` is started, told to end and
joined by the object that made it, and one still running after its join is an error.

This is ego's rule (``ego.nursery``), kept here in a few lines of the emulator's own: the
emulator never imports ego. As there, no thread is a daemon, and an emulator a program
leaves open is told to end at exit, before Python waits for its threads.
"""

from __future__ import annotations

import logging
import threading
import weakref
from collections.abc import Callable

__all__ = ["EmulatorThreadLeftError", "OwnedThread"]

log = logging.getLogger(__name__)

_OPEN: weakref.WeakSet[OwnedThread] = weakref.WeakSet()


class EmulatorThreadLeftError(RuntimeError):
    """An emulator's thread was still running when its owner gave up waiting for it."""


def _end_at_exit() -> None:
    for owned in list(_OPEN):
        try:
            owned.stop()
        except Exception:
            log.exception("ending %s at exit failed", owned.name)


# Before the interpreter joins its threads (atexit handlers run only after that join).
threading._register_atexit(_end_at_exit)  # type: ignore[attr-defined]


class OwnedThread:
    """``target`` in a thread named ``name``; ``stop`` is how its owner tells it to end."""

    def __init__(self, target: Callable[[], None], name: str, stop: Callable[[], None]) -> None:
        self.name = name
        self.stop = stop
        self._thread = threading.Thread(target=target, name=name)

    def start(self) -> None:
        _OPEN.add(self)
        self._thread.start()

    def join(self, timeout_s: float = 5.0) -> None:
        """Wait for the thread (told to end already); EmulatorThreadLeftError if it is
        still running after ``timeout_s``. From the thread itself: nothing to wait for."""
        _OPEN.discard(self)
        thread = self._thread
        if thread.ident is None or thread is threading.current_thread():
            return
        thread.join(timeout_s)
        if thread.is_alive():
            raise EmulatorThreadLeftError(f"{self.name} still running {timeout_s:g} s after close")
