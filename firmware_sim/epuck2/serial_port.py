"""The main processor's serial link on a real pseudo-terminal: USB CDC (selector 8) or
the UART to the radio module's Bluetooth (selector 3).

Pacing: over Bluetooth the F407 talks to the ESP32 on a 115200-baud UART
(MAIN:src/serial_comm.c:44-45), so each byte takes 10 bits of line time both ways and a
reply leaves in small chunks at that rate, plus an optional radio latency each way. USB
CDC has no baud rate: a full-speed USB link moves about a megabyte a second, far faster
than the firmware answers, so the USB port is modelled unpaced (bytes go as soon as the
firmware has them). Either way the firmware's own time (the 10 ms sleeps after USB
reads, the IMU filter's waits, K's calibration) delays its reply and its reading of the
next byte; bytes arriving meanwhile wait in the port's buffer, as they do in the CDC and
UART drivers' queues.
"""

from __future__ import annotations

import contextlib
import logging
import os
import select
import shutil
import tempfile
import threading
import time
import tty
from collections import deque

from firmware_sim.epuck2.asercom2 import Asercom2
from firmware_sim.threads import OwnedThread

__all__ = ["BANNER", "SerialPort"]

log = logging.getLogger(__name__)

#: Asercom2.c:153-160, sent once when run_asercom2 starts.
BANNER = (
    b"\x0c\x07WELCOME to the SerCom protocol on e-Puck\r\n"
    b'the EPFL education robot type "H" for help\r\n'
)
#: Bytes written to the pty at a time when paced.
CHUNK = 4


class SerialPort:
    """``firmware`` behind a pty at :attr:`path`; ``baud`` None means unpaced (USB)."""

    def __init__(self, firmware: Asercom2, lock: threading.RLock, *, baud: int | None,
                 latency_s: float = 0.0, blocking_writes: bool = False) -> None:  # fmt: skip
        if baud is not None and baud <= 0:
            raise ValueError(f"baud rate {baud} must be positive")
        if not 0.0 <= latency_s <= 10.0:
            raise ValueError(f"latency {latency_s} s is outside 0..10 s")
        self.firmware = firmware
        self._fw_lock = lock
        self.byte_s = 0.0 if baud is None else 10.0 / baud
        self.latency_s = latency_s
        #: USB: chSequentialStreamWrite waits while the host does not read, and so does the
        #: firmware (e_uart_char.c:69-74). UART: bytes the radio cannot pass on are lost.
        self.blocking_writes = blocking_writes
        self._write_blocked = False
        self._dir = tempfile.mkdtemp(prefix="ego-epuck2-")
        self.path = os.path.join(self._dir, "ttyEPUCK2")
        self._master, self._slave = os.openpty()
        tty.setraw(self._slave)
        os.set_blocking(self._master, False)
        os.symlink(os.ttyname(self._slave), self.path)
        self._inbox: deque[tuple[float, int]] = deque()
        self._out: deque[tuple[float, bytes]] = deque()
        self._in_free = self._out_free = self._busy_until = 0.0
        self._wake_r, self._wake_w = os.pipe()
        self._stop = threading.Event()
        self._closed = False
        self._thread = OwnedThread(self._run, "epuck2-serial", stop=self.close)
        self._schedule(BANNER, time.monotonic())

    def start(self) -> None:
        self._thread.start()

    def close(self) -> None:
        """Stop the thread, close the pty and remove its path; idempotent."""
        if self._closed:
            return
        self._closed = True
        self._stop.set()
        with contextlib.suppress(OSError):
            os.write(self._wake_w, b"x")
        try:
            self._thread.join()
        finally:
            for fd in (self._master, self._slave, self._wake_r, self._wake_w):
                with contextlib.suppress(OSError):
                    os.close(fd)
            shutil.rmtree(self._dir, ignore_errors=True)

    # -- the loop -------------------------------------------------------------------

    def _run(self) -> None:
        try:
            while not self._stop.is_set():
                self._tick()
        except Exception:  # a crashed port must say why, not hang its tests
            log.exception("e-puck2 serial port failed")
            raise

    def _timeout(self, now: float) -> float:
        if self._write_blocked:
            return 0.05  # select wakes us when the host reads
        due = [now + 0.05]
        if self._out:
            due.append(self._out[0][0])
        if self._inbox:
            due.append(max(self._inbox[0][0], self._busy_until))
        return max(0.0, min(due) - now)

    def _tick(self) -> None:
        writers = [self._master] if self._write_blocked else []
        readable, _, _ = select.select([self._master, self._wake_r], writers, [],
                                       self._timeout(time.monotonic()))  # fmt: skip
        if self._master in readable:
            try:
                data = os.read(self._master, 4096)
            except (BlockingIOError, InterruptedError):
                data = b""
            self._arrive(data, time.monotonic())
        self._process(time.monotonic())
        self._flush(time.monotonic())

    def _arrive(self, data: bytes, now: float) -> None:
        start = max(now, self._in_free)
        for i, byte in enumerate(data):
            self._inbox.append((start + (i + 1) * self.byte_s + self.latency_s, byte))
        self._in_free = start + len(data) * self.byte_s

    def _process(self, now: float) -> None:
        """Feed the firmware every byte that has arrived while it is free to read."""
        while (self._inbox and self._inbox[0][0] <= now and self._busy_until <= now
               and not self._write_blocked):  # fmt: skip
            arrived, byte = self._inbox.popleft()
            with self._fw_lock:
                emissions = self.firmware.feed(bytes([byte]))
            ready = max(arrived, self._busy_until)
            for emission in emissions:
                ready += emission.work_s
                if emission.data:
                    self._schedule(emission.data, ready)
            self._busy_until = ready

    def _schedule(self, data: bytes, ready: float) -> None:
        start = max(ready, self._out_free)
        step = CHUNK if self.byte_s else len(data)
        for i in range(0, len(data), step):
            chunk = data[i : i + step]
            due = start + (i + len(chunk)) * self.byte_s + self.latency_s
            self._out.append((due, chunk))
        self._out_free = start + len(data) * self.byte_s

    def _flush(self, now: float) -> None:
        self._write_blocked = False
        while self._out and self._out[0][0] <= now:
            due, chunk = self._out.popleft()
            try:
                written = os.write(self._master, chunk)
            except BlockingIOError:  # nobody reads: the host's buffer is full
                written = 0
            if written == len(chunk):
                continue
            if not self.blocking_writes:
                log.debug("e-puck2 serial: output overflow, %d bytes lost", len(chunk))
                continue
            self._out.appendleft((due, chunk[written:]))  # the firmware waits to write
            self._write_blocked = True
            return
