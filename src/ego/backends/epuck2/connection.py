"""One TCP connection to the e-puck2's radio, and the thread that keeps reading it.

The radio streams once commanded, whether or not anyone reads (ESP:socket_e-puck2.c:
182-196), and its sends block (a client that stops reading stalls the robot's loop), so
a connection is read all the time by its own thread, started by :class:`WifiConnection`
in a :class:`~ego.nursery.Nursery` and stopped and joined by its
:meth:`~WifiConnection.close` (a reader still running 5 s later is a ThreadLeakError); a
program that exits with the connection open has it closed before Python waits for its
threads. What the thread heard is kept as the newest of each kind, numbered, for the
channel to wait on.

A connection is never left without a valid command: the constructor sends its first
command as soon as the TCP handshake is done, before anything else can fail, because a
client that leaves before one valid 0x80 command wedges the radio for good
(socket_e-puck2.c:164-196).
"""

from __future__ import annotations

import contextlib
import socket
import threading
import time
from dataclasses import dataclass

from ego.backends.epuck2.wifi_packets import (
    Closed,
    EmptyReply,
    ImageReply,
    NeedData,
    ReplyParser,
    SensorReply,
)
from ego.errors import EgoError, LinkError, LinkTimeoutError, PortNotFoundError
from ego.nursery import Nursery

__all__ = ["Heard", "WifiConnection", "connect"]

#: A send's deadline, and how often the reader looks whether it must stop (close()
#: wakes it at once by shutting the socket down).
IO_TIMEOUT_S = 2.0


@dataclass
class Heard:
    """What the reader heard last, each kind numbered from 1 (0: none yet)."""

    sensors: SensorReply | None = None
    sensors_seq: int = 0
    image: bytes | None = None
    image_seq: int = 0
    empties: int = 0
    bytes_received: int = 0
    #: Why the connection ended (None while it lives).
    lost: str | None = None


def connect(name: str, address: tuple[str, int], first: bytes, timeout_s: float) -> socket.socket:
    """A socket to the radio at ``address`` that has sent ``first`` (a valid command).

    Raises PortNotFoundError for a refused connection, LinkTimeoutError when the
    handshake does not complete within ``timeout_s``, LinkError for the rest; ``name``
    (the port) begins each message.
    """
    try:
        sock = socket.create_connection(address, timeout=timeout_s)
    except ConnectionRefusedError:
        raise PortNotFoundError(
            f"{name}: connection refused at {address[0]}:{address[1]}: is the robot on, "
            "with its selector at 15 (WiFi) and the radio's WiFi firmware?"
        ) from None
    except TimeoutError:
        raise LinkTimeoutError(
            f"{name}: no answer from {address[0]}:{address[1]} within {timeout_s} s"
        ) from None
    except OSError as exc:
        raise LinkError(f"{name}: cannot reach {address[0]}:{address[1]}: {exc}") from exc
    try:
        sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        sock.sendall(first)  # at once: see the module's doc (the wedge)
    except OSError as exc:
        sock.close()
        raise LinkError(f"{name}: the connection failed at its first command: {exc}") from exc
    return sock


class WifiConnection:
    """A connected socket (it sent its first command) and its reader thread."""

    def __init__(self, name: str, sock: socket.socket) -> None:
        self.name = name
        self._sock = sock
        self._send_lock = threading.Lock()
        self._changed = threading.Condition()
        self.heard = Heard()
        self._stop = threading.Event()
        sock.settimeout(IO_TIMEOUT_S)
        self._nursery = Nursery(f"epuck2 WiFi {name}", at_exit=self.close)
        self._nursery.start_thread(self._read, name="epuck2-wifi-reader")

    def send(self, command: bytes) -> None:
        """Send one 21-byte command; LinkError when the connection is gone."""
        with self._send_lock:
            try:
                self._sock.sendall(command)
            except OSError as exc:
                self._end(f"sending failed: {exc}")
                raise LinkError(f"{self.name}: sending failed: {exc}") from exc

    def wait(self, ready: str, after: int, deadline: float) -> Heard | None:
        """Wait until the count ``ready`` (a :class:`Heard` field) passes ``after``, or
        the connection ends, or ``deadline`` (time.monotonic()) passes; what was heard
        then, or None at the deadline."""
        with self._changed:
            while getattr(self.heard, ready) <= after and self.heard.lost is None:
                left = deadline - time.monotonic()
                if left <= 0:
                    return None
                self._changed.wait(left)
            return self.heard

    def close(self) -> None:
        """Stop the reader, join it, close the socket; idempotent. ThreadLeakError (the
        socket closed all the same) if the reader is still running 5 s later."""
        self._stop.set()
        with contextlib.suppress(OSError):
            self._sock.shutdown(socket.SHUT_RDWR)
        try:
            self._nursery.close()
        finally:
            self._sock.close()
            self._end("closed")

    def _end(self, why: str) -> None:
        with self._changed:
            if self.heard.lost is None:
                self.heard.lost = why
            self._changed.notify_all()

    def _read(self) -> None:
        parser = ReplyParser()
        buffer = bytearray(65536)
        try:
            while not self._stop.is_set():
                try:
                    n = self._sock.recv_into(buffer)
                except TimeoutError:
                    continue
                parser.receive_data(memoryview(buffer)[:n])
                self._take(parser, n)
                if n == 0:
                    self._end("the robot closed the connection")
                    return
        except (OSError, EgoError) as exc:  # a reset, or bytes out of step (FrameError)
            self._end(str(exc) or type(exc).__name__)

    def _take(self, parser: ReplyParser, n: int) -> None:
        with self._changed:
            heard = self.heard
            heard.bytes_received += n
            while not isinstance(event := parser.next_event(), NeedData | Closed):
                if isinstance(event, SensorReply):
                    heard.sensors, heard.sensors_seq = event, heard.sensors_seq + 1
                elif isinstance(event, ImageReply):
                    heard.image, heard.image_seq = event.data, heard.image_seq + 1
                elif isinstance(event, EmptyReply):
                    heard.empties += 1
            self._changed.notify_all()
