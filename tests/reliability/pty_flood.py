"""A real pty between ego and an emulated robot's own pty that, once told, never stops
sending: a peer babbling on a serial line (a wrong device, a shorted line, a runaway
firmware). Every byte passes both ways until :meth:`FloodingRelay.flood`; from then on the
robot side is cut and ego's side gets bytes as fast as the pty takes them."""

from __future__ import annotations

import contextlib
import os
import pty
import select
import threading
import tty
from types import TracebackType

#: Not a reply of any command, nor the banner: the letter U, 0x55 (a UART's test pattern).
FLOOD = b"\x55" * 4096


class FloodingRelay:
    """ego opens :attr:`path`; the emulator's pty is ``robot_path``. ``close`` joins."""

    def __init__(self, robot_path: str, bytes_per_s: int | None = None) -> None:
        self._master, self._slave = pty.openpty()
        tty.setraw(self._slave)
        self.path = os.ttyname(self._slave)
        self._robot = os.open(robot_path, os.O_RDWR | os.O_NOCTTY)
        tty.setraw(self._robot)
        os.set_blocking(self._master, False)
        self._stop_r, self._stop_w = os.pipe()
        self._flooding = threading.Event()
        #: None: as fast as the pty takes them; else about this many bytes a second (a
        #: babbling device at a UART's rate: 11520 at 115200 baud).
        self._chunk = FLOOD if bytes_per_s is None else FLOOD[: max(1, bytes_per_s // 100)]
        self._pause_s = 0.0 if bytes_per_s is None else 0.01
        #: Bytes sent to ego since the flood began.
        self.flooded = 0
        self._thread = threading.Thread(target=self._run, name="test-pty-flood")
        self._thread.start()

    def flood(self) -> None:
        self._flooding.set()

    def _run(self) -> None:
        while True:
            flooding = self._flooding.is_set()
            readers = [self._master, self._stop_r] + ([] if flooding else [self._robot])
            writers = [self._master] if flooding else []
            readable, writable, _ = select.select(readers, writers, [], 0.05)
            if writable and self._pause_s:  # paced: one chunk every 10 ms
                self._stop_wait(self._pause_s)
            if self._stop_r in readable:
                return
            if self._master in readable:
                try:
                    data = os.read(self._master, 4096)
                except (BlockingIOError, OSError):
                    data = b""
                if data and not flooding:
                    os.write(self._robot, data)
            if self._robot in readable:
                os.write(self._master, os.read(self._robot, 4096))
            if self._master in writable:
                with contextlib.suppress(BlockingIOError, OSError):  # full: the next turn
                    self.flooded += os.write(self._master, self._chunk)

    def _stop_wait(self, timeout_s: float) -> None:
        select.select([self._stop_r], [], [], timeout_s)

    def close(self) -> None:
        os.write(self._stop_w, b"x")
        self._thread.join()
        for fd in (self._master, self._slave, self._robot, self._stop_r, self._stop_w):
            os.close(fd)

    def __enter__(self) -> FloodingRelay:
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        self.close()
