"""The emulated dsPIC on a real pseudo-terminal, paced at the line's baud rate.

pyserial opens :attr:`Emulator.path` like a real port. The path is a stable symlink to
the current pty, so that a "disconnect" fault can make the port vanish and come back
under the same name, as a re-plugged serial adapter does under ``/dev/serial/by-id``.

Pacing: each byte takes 10 bits of line time both ways (43.4 us at 230400), so a batch
is heard only once its last byte would have crossed the wire, and its reply leaves in
small chunks at line rate; an optional processing delay per command reproduces the
thesis' measured 84 us/byte.
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
from collections.abc import Iterable
from types import TracebackType

from firmware_sim.dspic import BANNER, BatchRecord, Dspic, Emission
from firmware_sim.faults import FaultPlan, FaultSpec, FaultTimings
from firmware_sim.i2c import OveroBus
from firmware_sim.threads import OwnedThread
from firmware_sim.world import World

__all__ = ["Emulator"]

log = logging.getLogger(__name__)

#: Bytes written to the pty at a time: small enough that stray bytes right behind a
#: reply arrive within a few byte times, as they would on a real UART.
CHUNK = 4


class Emulator:
    """A dsPIC + world behind a pty; ``with Emulator() as emu: Robot(emu.path)``.

    Runs in a background thread (:meth:`start`) or in the calling thread
    (:meth:`serve_forever`, for ``python -m firmware_sim``). In Overo mode (the stock
    firmware in selector 10) :attr:`i2c` is the robot's I2C bus as the Overo sees it,
    with the ground module and, on a rev 1.3, the LSM330; None in any other mode, where
    the dsPIC is the bus's master.
    """

    def __init__(
        self,
        firmware: str = "webots",
        *,
        baud: int | None = None,
        processing_delay_s: float = 0.0,
        faults: Iterable[FaultSpec] = (),
        seed: int | None = None,
        timings: FaultTimings | None = None,
        world: World | str | None = None,
        hardware_version: int = 0xFFFF,
        rev13: bool = False,
        selector: int | None = None,
        ground_module: bool = True,
        latency_s: float = 0.0,
        dspic_work: bool = True,
    ) -> None:
        if isinstance(world, str):
            from firmware_sim.worlds import load_world

            world = load_world(world, seed)  # a built-in world's name or a file's path
        self.world = world or World(seed=seed)
        self.dspic = Dspic(
            self.world,
            firmware,
            hardware_version,
            rev13=rev13,
            selector=selector,
            ground_module=ground_module,
            work=dspic_work,
        )
        #: The I2C bus the firmware leaves to the Overo (firmware_sim.i2c), else None.
        self.i2c = (
            OveroBus(self.world, ground_module=ground_module, rev13=rev13)
            if self.dspic.overo
            else None
        )
        baud = self.dspic.line_baud if baud is None else baud
        if baud <= 0:
            raise ValueError(f"baud rate {baud} must be positive")
        if not 0.0 <= latency_s <= 10.0:
            raise ValueError(f"latency {latency_s} s is outside 0..10 s")
        #: A Bluetooth SPP link's own delay, each way (a few ms; 0 on a wire).
        self.latency_s = latency_s
        self.plan = FaultPlan(faults, seed, timings or FaultTimings())
        self.baud = baud
        self.byte_s = 10.0 / baud
        self.processing_delay_s = processing_delay_s
        #: Every answered batch, newest last: the ground truth tests compare against.
        self.history: deque[BatchRecord] = deque(maxlen=100_000)
        self._dir = tempfile.mkdtemp(prefix="ego-sim-")
        self.path = os.path.join(self._dir, "ttyEPUCK")
        self._master = -1
        self._slave = -1
        self._out: deque[tuple[float, bytes]] = deque()
        self._out_free = 0.0
        self._in_free = 0.0
        self._stalled_until = 0.0
        self._replug_at: float | None = None
        self._wake_r, self._wake_w = os.pipe()
        self._stop = threading.Event()
        self._thread: OwnedThread | None = None
        self._closed = False
        self._plug()
        self._schedule(BANNER, time.monotonic())  # power-on banner, drained at open

    # -- lifecycle -----------------------------------------------------------------------

    def start(self) -> Emulator:
        self._thread = OwnedThread(self.serve_forever, "ego-sim", stop=self.stop)
        self._thread.start()
        return self

    def stop(self) -> None:
        """Stop serving, close the pty and remove its symlink; idempotent."""
        if self._closed:
            return
        self._closed = True
        self._stop.set()
        with contextlib.suppress(OSError):
            os.write(self._wake_w, b"x")
        try:
            if self._thread is not None:
                self._thread.join()
        finally:
            self._unplug()
            for fd in (self._wake_r, self._wake_w):
                with contextlib.suppress(OSError):
                    os.close(fd)
            shutil.rmtree(self._dir, ignore_errors=True)

    def __enter__(self) -> Emulator:
        return self.start()

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        self.stop()

    @property
    def firmware(self) -> str:
        return self.dspic.firmware

    def inject(self, kind: str, batch: int | None = None) -> None:
        """Strike batch number ``batch`` with fault ``kind`` (a trigger, beside the rates):
        1-based, as :attr:`batches` and ``history``'s records count them; None strikes
        the next batch to arrive, which races a batch still on its way (an actuator-only
        batch is not answered: its sender does not wait for it)."""
        self.plan.force(kind, batch)

    @property
    def batches(self) -> int:
        """How many batches the dsPIC has parsed so far."""
        return self.dspic.batches

    # -- the pty -------------------------------------------------------------------------

    def _plug(self) -> None:
        self._master, self._slave = os.openpty()
        tty.setraw(self._slave)  # no echo, no CR/LF translation before pyserial opens it
        # Holding the slave open keeps the master readable without EIO between clients.
        os.set_blocking(self._master, False)
        tmp = self.path + ".new"
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp)
        os.symlink(os.ttyname(self._slave), tmp)
        os.replace(tmp, self.path)

    def _unplug(self) -> None:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(self.path)
        for fd in (self._master, self._slave):
            if fd >= 0:
                with contextlib.suppress(OSError):
                    os.close(fd)
        self._master = self._slave = -1
        self._out.clear()

    # -- the loop ------------------------------------------------------------------------

    def serve_forever(self) -> None:
        try:
            while not self._stop.is_set():
                self._tick()
        except Exception:  # a crashed emulator must say why, not hang its tests
            log.exception("emulator loop failed")
            raise

    def _tick(self) -> None:
        now = time.monotonic()
        if self._replug_at is not None:
            if now < self._replug_at:
                select.select([self._wake_r], [], [], self._replug_at - now)
                return
            self._replug_at = None
            self._plug()
            log.info("emulator: port back at %s", self.path)
        timeout = 0.05
        if self._out:
            timeout = min(timeout, max(0.0, self._out[0][0] - now))
        readable, _, _ = select.select([self._master, self._wake_r], [], [], timeout)
        if self._master in readable:
            try:
                data = os.read(self._master, 4096)
            except (BlockingIOError, InterruptedError):
                data = b""
            if data:
                self._receive(data, time.monotonic())
        self._flush(time.monotonic())

    def _flush(self, now: float) -> None:
        while self._out and self._out[0][0] <= now and self._master >= 0:
            _, chunk = self._out.popleft()
            try:
                os.write(self._master, chunk)
            except BlockingIOError:  # nobody reads: a real UART's FIFO would overflow too
                log.debug("emulator: output overflow, %d bytes lost", len(chunk))

    def _schedule(self, data: bytes, ready: float, together_from: int | None = None) -> None:
        """Send ``data`` from ``ready`` on, each chunk once its last byte has crossed the
        wire; the bytes from ``together_from`` on in one write (faults.Mangled)."""
        start = max(ready, self._out_free)
        cut = len(data) if together_from is None else together_from
        for i in range(0, cut, CHUNK):
            chunk = data[i : min(i + CHUNK, cut)]
            self._out.append((start + (i + len(chunk)) * self.byte_s, chunk))
        if cut < len(data):
            self._out.append((start + len(data) * self.byte_s, data[cut:]))
        self._out_free = start + len(data) * self.byte_s

    def _receive(self, data: bytes, now: float) -> None:
        if now < self._stalled_until:
            return  # a hung dsPIC hears nothing
        data, corrupted = self.plan.corrupt_chunk(data, self.dspic.batches + 1)
        # The last byte of this chunk has crossed the wire only after its line time.
        arrived = max(now, self._in_free) + len(data) * self.byte_s + self.latency_s
        self._in_free = arrived - self.latency_s
        for emission in self.dspic.feed(data):
            if emission.kind == "reply":
                self._answer(emission, arrived, corrupted)
                corrupted = False
                continue
            ready = arrived + emission.after_s
            if emission.deaf_s:
                # K: the dsPIC calibrates without reading the line; what arrives
                # meanwhile is not heard (a real one keeps up to 64 bytes in a ring
                # with no overflow check; dropping them all is the emulator's choice).
                self._stalled_until = arrived + emission.deaf_s
            self._schedule(emission.data, ready + self.latency_s)

    def _answer(self, emission: Emission, arrived: float, corrupted: bool) -> None:
        record = emission.record
        assert record is not None
        kinds = self.plan.for_batch(record.index, has_reply=bool(emission.data))
        record.faults = (["corrupt"] if corrupted else []) + kinds
        self.history.append(record)
        ready = arrived + self.processing_delay_s * (len(record.commands) + 1) + record.work_s
        ready += self.latency_s
        if "reset" in kinds:
            self.dspic.reset()
            first_line = BANNER.index(b"\n") + 1
            self._schedule(BANNER[:first_line], ready)
            self._schedule(BANNER[first_line:], ready + self.plan.timings.banner_gap_s)
            return
        if "disconnect" in kinds:
            self._unplug()
            self._replug_at = time.monotonic() + self.plan.timings.replug_s
            log.info("emulator: port unplugged for %.2f s", self.plan.timings.replug_s)
            return
        if "stall" in kinds:
            self._stalled_until = ready + self.plan.timings.stall_s
            return
        if "delay" in kinds:
            ready += self.plan.timings.delay_s
        mangled = self.plan.mangle_reply(kinds, emission.data)
        if mangled.data:
            self._schedule(mangled.data, ready, mangled.together_from)
