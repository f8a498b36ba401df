"""Test doubles: a scripted transport that answers each write from a script, and fast settings.

Hardware is injected, never monkeypatched: tests hand a
:class:`ScriptedTransport` to ``Link`` the way a robot hands it a serial port.
"""

from __future__ import annotations

import time
from collections import deque
from collections.abc import Callable, Iterable

from ego.errors import LinkLostError
from ego.seam.profile import DEFAULT_BAUD
from ego.serial.link import LinkSettings
from ego.serial.transport import Transport
from firmware_sim import FaultTimings

#: One answer of a script: bytes that arrive after the write, an exception the write
#: raises, or a function of the written bytes that returns what arrives.
Answer = bytes | BaseException | Callable[[bytes], bytes]

#: Link settings that keep fault recovery quick in tests; the defaults are tested too.
FAST_LINK = LinkSettings(
    reply_timeout_s=0.01,
    resync_quiet_s=0.02,
    resync_max_s=0.5,
    reconnect_timeout_s=1.0,
    line_timeout_s=0.1,
)
#: Fault timings to match: a delay beyond a reply timeout, a stall beyond all retries.
FAST_FAULTS = FaultTimings(delay_s=0.06, stall_s=0.3, replug_s=0.15)
#: Settings for the scripted transport, where nothing travels: every wait is a timeout.
INSTANT_LINK = LinkSettings(
    reply_timeout_s=0.002,
    wire_factor=0.0,
    trailing_guard_s=0.0,
    resync_quiet_s=0.001,
    resync_max_s=0.05,
    reconnect_timeout_s=0.1,
    line_timeout_s=0.005,
)


class ScriptedTransport(Transport):
    """A transport whose far end plays ``script``: one answer per write, in order.

    Once the script runs out, writes get no answer (a silent dsPIC). Every write and
    read is logged in :attr:`events`, so tests can check what the link sent and whether
    it waited for anything. A read with nothing to return sleeps out its timeout, as a
    real port does.
    """

    name = "scripted"

    def __init__(
        self,
        script: Iterable[Answer] = (),
        *,
        incoming: bytes = b"",
        reopen: Iterable[BaseException | None] = (),
        baudrate: int | None = DEFAULT_BAUD,
        latency_s: float = 0.0,
    ) -> None:
        self.script: deque[Answer] = deque(script)
        self.incoming = bytearray(incoming)
        #: Results of successive reopen() calls: an exception to raise, or None to succeed.
        #: Once exhausted, reopen() succeeds.
        self.reopen_results: deque[BaseException | None] = deque(reopen)
        self.baudrate = baudrate
        self.latency_s = latency_s
        self.events: list[tuple[str, bytes | int]] = []
        self.reopened = 0
        self.closed = False

    @property
    def writes(self) -> list[bytes]:
        return [data for kind, data in self.events if kind == "write"]  # type: ignore[misc]

    def answer(self, data: bytes) -> None:
        """Make ``data`` arrive now, as if the far end sent it unprompted."""
        self.incoming += data

    def write(self, data: bytes) -> None:
        if self.closed:
            raise LinkLostError(f"{self.name}: port is closed")
        self.events.append(("write", bytes(data)))
        if not self.script:
            return
        item = self.script.popleft()
        if isinstance(item, BaseException):
            self.closed = isinstance(item, LinkLostError)  # a lost port stays lost
            raise item
        self.incoming += item(bytes(data)) if callable(item) else item

    def read(self, size: int, timeout_s: float) -> bytes:
        if self.closed:
            raise LinkLostError(f"{self.name}: port is closed")
        self.events.append(("read", size))
        if not self.incoming:
            if timeout_s > 0:
                time.sleep(timeout_s)
            return b""
        data = bytes(self.incoming[:size])
        del self.incoming[:size]
        return data

    def reopen(self) -> None:
        self.reopened += 1
        result = self.reopen_results.popleft() if self.reopen_results else None
        if result is not None:
            raise result
        self.closed = False

    def close(self) -> None:
        self.closed = True
