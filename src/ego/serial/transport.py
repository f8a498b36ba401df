"""The one byte-stream interface under the link: a serial port, a pty, or a network robot.

Every transport offers ``write``, ``read(size, timeout_s)`` and ``close``; the shared
``read_exactly`` and ``drain`` are written once here. :class:`SerialTransport` opens
anything pyserial can (``/dev/ttyS0``, a pty path, ``loop://``, ``socket://host:port``,
``spy://...`` for a hex dump of the wire).
"""

from __future__ import annotations

import abc
import contextlib
import errno
import logging
import numbers
import os
import select
import time
from collections.abc import Iterator
from types import TracebackType

import serial

from ego.errors import (
    LinkLostError,
    LinkTimeoutError,
    OutOfRangeError,
    PortBusyError,
    PortNotFoundError,
)
from ego.seam.profile import DEFAULT_BAUD
from ego.serial.port_holder import find_port_holder

__all__ = ["MAX_BAUD", "MIN_BAUD", "SerialTransport", "Transport", "check_baudrate"]

log = logging.getLogger(__name__)


#: The slowest line ego's timings hold at: the stop batch (D, ten L, E) must be confirmed
#: within the link's timeouts (the e-puck's own lines run at 115200 and 230400).
MIN_BAUD = 9600
#: The fastest rate Linux serial drivers offer (B4000000); above, termios cannot say it.
MAX_BAUD = 4_000_000


def check_baudrate(baudrate: object) -> int:
    """``baudrate`` as an int within MIN_BAUD..MAX_BAUD, else TypeError or OutOfRangeError.

    pyserial would open a port at 0 baud (which hangs a POSIX line up), report a negative
    rate as a port it cannot open, and overflow on an absurd one.
    """
    if isinstance(baudrate, bool) or not isinstance(baudrate, numbers.Integral):
        raise TypeError(f"baud rate must be an int, not {type(baudrate).__name__}")
    rate = int(baudrate)
    if rate <= 0:
        raise OutOfRangeError(f"baud rate {rate} must be positive (the Overo's is 230400)")
    if not MIN_BAUD <= rate <= MAX_BAUD:
        raise OutOfRangeError(
            f"baud rate {rate} is outside {MIN_BAUD}..{MAX_BAUD}: below, the robot's stop "
            "cannot be confirmed in time; the e-puck's lines run at 230400 (Overo) and "
            "115200 (Bluetooth)"
        )
    return rate


class Transport(abc.ABC):
    """A byte stream to a robot's dsPIC. Subclasses implement the four primitives."""

    #: Where the bytes go, for messages ("/dev/ttyS0", "tcp://robot:4242").
    name: str = "?"
    #: Line rate in bits per second, for reply timeouts; None where it means nothing.
    baudrate: int | None = None
    #: Extra time a reply may take beyond the line's wire time (a network hop, a
    #: server's own retries); the link adds it to every reply timeout.
    latency_s: float = 0.0
    #: Whether the link's resynchronisation bytes reach the dsPIC (and its ``V`` answer
    #: comes back); a relay that resynchronises the line itself says False.
    relays_resync: bool = True

    @abc.abstractmethod
    def write(self, data: bytes) -> None:
        """Send all of ``data`` (raise LinkLostError if the line is gone)."""

    @abc.abstractmethod
    def read(self, size: int, timeout_s: float) -> bytes:
        """Up to ``size`` bytes, returning early once ``size`` arrived; b'' on timeout."""

    @abc.abstractmethod
    def close(self) -> None:
        """Release the line; calling it twice is harmless."""

    def waiting_until(self, deadline_s: float) -> None:
        """The controller waits out its step until ``deadline_s`` (time.monotonic()).

        A serial line needs nothing; a network transport keeps its session alive until
        then, and only then: a controller that stops stepping must let the server's
        deadman stop the robot.
        """
        return  # a serial line has no session to keep alive

    def reopen(self) -> None:
        """Open the line again after it was lost (a re-plugged port). Default: cannot."""
        raise LinkLostError(f"{self.name}: this transport cannot reconnect")

    def pending(self) -> bytes:
        """Bytes already waiting, without blocking (stale bytes before a new batch)."""
        return self.read(4096, 0.0)

    def read_line(self, timeout_s: float) -> bytes:
        """One line up to and including ``\\n``, or what came before ``timeout_s``."""
        deadline = time.monotonic() + timeout_s
        line = bytearray()
        while not line.endswith(b"\n"):
            remaining = deadline - time.monotonic()
            if remaining <= 0:
                break
            line += self.read(1, remaining)
        return bytes(line)

    def read_exactly(self, size: int, timeout_s: float, expected_s: float = 0.0) -> bytes:
        """Exactly ``size`` bytes within ``timeout_s``, or LinkTimeoutError with what came.

        ``expected_s``: when the reply cannot have arrived sooner (its wire time), a hint
        a transport may sleep on rather than wake for nothing.
        """
        deadline = time.monotonic() + timeout_s
        data = bytearray()
        while len(data) < size:
            remaining = deadline - time.monotonic()
            if remaining <= 0:
                break
            data += self.read(size - len(data), remaining)
        return self._complete(data, size, timeout_s)

    def _complete(self, data: bytearray, size: int, timeout_s: float) -> bytes:
        if len(data) < size:
            err = LinkTimeoutError(
                f"{self.name}: {len(data)} of {size} reply bytes after {timeout_s * 1e3:.1f} ms"
            )
            err.partial = bytes(data)  # type: ignore[attr-defined]
            raise err
        return bytes(data)

    def trailing(self, guard_s: float) -> bytes:
        """A byte that arrives within ``guard_s`` (one that should not be there), or b""."""
        return self.read(1, guard_s)

    def drain(self, quiet_s: float, max_s: float, max_bytes: int = 1 << 16) -> bytes:
        """Read and return whatever arrives until the line has been quiet for ``quiet_s``,
        for ``max_s`` at most and ``max_bytes`` at most (a line that never stops)."""
        deadline = time.monotonic() + max_s
        drained = bytearray()
        while len(drained) < max_bytes:
            remaining = deadline - time.monotonic()
            if remaining <= 0:
                break
            chunk = self.read(min(4096, max_bytes - len(drained)), min(quiet_s, remaining))
            if not chunk:
                break
            drained += chunk
        return bytes(drained)

    def __enter__(self) -> Transport:
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        self.close()

    def __repr__(self) -> str:
        return f"<{type(self).__name__} {self.name}>"


def port_busy_error(port: str) -> PortBusyError:
    """The error for a port another process has locked, naming that process if it can."""
    holder = find_port_holder(port)
    if holder is None:
        who = "another process"
    elif holder.pid == os.getpid():
        who = "this process (another Robot on the same port)"
    else:
        who = f"process {holder.pid} ({holder.command})"
    return PortBusyError(
        f"port {port!r} is held by {who}: one controller drives a robot at a time; "
        "stop the other one first",
        holder_pid=holder.pid if holder else None,
    )


#: How long a write may wait for the line to take it before the line counts as lost.
WRITE_TIMEOUT_S = 2.0

#: The most latency a serial transport may add to each reply timeout: beyond it a lost
#: reply would hold the controller for longer than a step can mean anything.
MAX_LATENCY_S = 60.0

#: Sleep through this share of the time the bytes cannot be here sooner than: the rest of
#: it covers a sleep that wakes late.
_EARLY = 0.85


class SerialTransport(Transport):
    """Any pyserial port or URL, 8N1 without flow control (docs/protocol.md: Line).

    ``latency_s`` (0 for a real port) is added to every reply timeout: the sim backend
    gives its in-process emulator the host's scheduling and a modelled radio's delay.
    """

    def __init__(self, url: str, baudrate: int = DEFAULT_BAUD, latency_s: float = 0.0) -> None:
        self.baudrate: int = check_baudrate(baudrate)
        if not 0.0 <= latency_s <= MAX_LATENCY_S:
            raise OutOfRangeError(
                f"{url}: a reply latency of {latency_s} s is outside 0..{MAX_LATENCY_S:g} s"
            )
        self.latency_s = latency_s
        self.name = url
        self._port: serial.SerialBase | None = None
        self._timeout: float | None = None
        self._open()

    def _open(self) -> None:
        try:
            port = serial.serial_for_url(
                self.name,
                baudrate=self.baudrate,
                bytesize=serial.EIGHTBITS,
                parity=serial.PARITY_NONE,
                stopbits=serial.STOPBITS_ONE,
                xonxoff=False,
                rtscts=False,
                timeout=0,
                # A write the line never takes (a wedged pty, a stalled driver) must fail
                # as a lost line, not hang the controller: a step's batch takes 4 ms.
                write_timeout=WRITE_TIMEOUT_S,
                # flock(2) the port: a second controller on the same robot is refused at
                # open instead of interleaving its batches with ours (URLs ignore it).
                exclusive=True,
            )
        except (serial.SerialException, OSError, ValueError) as exc:
            if getattr(exc, "errno", None) in (errno.EWOULDBLOCK, errno.EAGAIN):
                raise port_busy_error(self.name) from exc
            raise PortNotFoundError(f"cannot open port {self.name!r}: {exc}") from exc
        self._port = port
        self._timeout = 0

    @contextlib.contextmanager
    def _io(self, what: str) -> Iterator[serial.SerialBase]:
        if self._port is None:
            raise LinkLostError(f"{self.name}: port is closed")
        try:
            yield self._port
        except (serial.SerialException, OSError) as exc:
            raise LinkLostError(f"{self.name}: {what} failed: {exc}") from exc

    def write(self, data: bytes) -> None:
        with self._io("write") as port:
            port.write(data)

    def read(self, size: int, timeout_s: float) -> bytes:
        with self._io("read") as port:
            # Setting pyserial's timeout reconfigures the port (a tcsetattr), so only
            # when it changes.
            timeout = max(0.0, timeout_s)
            if timeout != self._timeout:
                port.timeout = timeout
                self._timeout = timeout
            return bytes(port.read(size))

    def pending(self) -> bytes:
        with self._io("read") as port:
            waiting = int(port.in_waiting)  # type: ignore[attr-defined]  # FIONREAD, cheap
        return self.read(waiting, 0.0) if waiting else b""

    # A reply is read from the port's descriptor against an absolute deadline: pyserial's
    # own read would reconfigure the port (a tcsetattr) whenever the timeout changes, and
    # its select loop wakes at every byte. The reply cannot come sooner than its wire time,
    # and once it flows the rest comes at the line rate: sleep through both.

    def _fd(self) -> int | None:
        fd = getattr(self._port, "fd", None)  # a POSIX serial port or pty; URLs have none
        return fd if isinstance(fd, int) else None

    def read_exactly(self, size: int, timeout_s: float, expected_s: float = 0.0) -> bytes:
        fd = self._fd()
        if fd is None:
            return super().read_exactly(size, timeout_s)
        start = time.monotonic()
        deadline = start + timeout_s
        data = bytearray()
        byte_s = 10.0 / self.baudrate
        if expected_s > 0:
            time.sleep(min(expected_s * _EARLY, timeout_s))
        while len(data) < size:
            remaining = deadline - time.monotonic()
            if remaining <= 0:
                break
            data += self._read_fd(fd, size - len(data), remaining)
            left = size - len(data)
            if left > 1 and data:
                time.sleep(min(left * byte_s * _EARLY, max(0.0, deadline - time.monotonic())))
        return self._complete(data, size, timeout_s)

    def trailing(self, guard_s: float) -> bytes:
        fd = self._fd()
        return self._read_fd(fd, 1, guard_s) if fd is not None else super().trailing(guard_s)

    def _read_fd(self, fd: int, size: int, timeout_s: float) -> bytes:
        """Up to ``size`` bytes within ``timeout_s``, from the descriptor itself."""
        with self._io("read"):
            ready, _, _ = select.select([fd], [], [], max(0.0, timeout_s))
            if not ready:
                return b""
            try:
                chunk = os.read(fd, size)
            except BlockingIOError:
                return b""
            if not chunk:  # ready but empty: the device went away (pyserial says the same)
                raise serial.SerialException("readiness to read but no data: device gone")
            return chunk

    def reopen(self) -> None:
        self.close()
        self._open()
        log.info("%s: port reopened", self.name)

    def close(self) -> None:
        port, self._port = self._port, None
        if port is not None:
            with contextlib.suppress(serial.SerialException, OSError):
                port.close()

    @property
    def is_open(self) -> bool:
        return self._port is not None
