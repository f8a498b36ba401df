"""Stand-ins for what is not an e-puck, and a subprocess that is never left behind.

A pseudo-terminal opened here plays a serial device that answers nothing, echoes every
byte, or answers every line like a modem, so that tests can point ego at a port that is
there but is not a robot.
"""

from __future__ import annotations

import contextlib
import os
import pty
import select
import threading
import tty
from collections.abc import Callable
from types import TracebackType


class FakeDevice:
    """A pty whose far end plays ``answer`` (bytes in, bytes out), or stays silent.

    ``path`` is the device to open, as a USB-serial adapter's would be. ``close`` ends the
    thread and closes both ends.
    """

    def __init__(self, answer: Callable[[bytes], bytes] | None = None) -> None:
        self._master, self._slave = pty.openpty()
        tty.setraw(self._slave)
        self.path = os.ttyname(self._slave)
        self._answer = answer
        self._stop_r, self._stop_w = os.pipe()
        self._thread = threading.Thread(target=self._serve, name="fake-device")
        self._thread.start()

    def _serve(self) -> None:
        while True:
            ready, _, _ = select.select([self._master, self._stop_r], [], [])
            if self._stop_r in ready:
                return
            try:
                data = os.read(self._master, 4096)
            except OSError:
                return
            if self._answer is not None:
                reply = self._answer(data)
                if reply:
                    os.write(self._master, reply)

    def close(self) -> None:
        os.write(self._stop_w, b"x")
        self._thread.join(timeout=5)
        for fd in (self._master, self._slave, self._stop_r, self._stop_w):
            with contextlib.suppress(OSError):
                os.close(fd)
        assert not self._thread.is_alive(), "the fake device's thread did not end"

    def __enter__(self) -> FakeDevice:
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        self.close()


def silent_device() -> FakeDevice:
    """A port with nothing behind it that talks: an unplugged adapter, a robot switched off."""
    return FakeDevice()


def echo_device() -> FakeDevice:
    """A port that sends back every byte (a loopback plug, a terminal in echo mode)."""
    return FakeDevice(lambda data: data)


def modem_device() -> FakeDevice:
    """A port that answers every line with ``OK`` (a modem, a GPS, another board's shell)."""
    pending = bytearray()

    def answer(data: bytes) -> bytes:
        pending.extend(data)
        lines = pending.count(b"\n")
        del pending[: pending.rfind(b"\n") + 1]
        return b"OK\r\n" * lines

    return FakeDevice(answer)


def read_line(stream: object, timeout_s: float) -> str:
    """One line of a subprocess's output, or '' if none came within ``timeout_s``."""
    ready, _, _ = select.select([stream], [], [], timeout_s)
    return stream.readline() if ready else ""  # type: ignore[attr-defined]
