"""The Unix socket the shim connects to: one thread, owned, stopped and joined by close.

Each connection is one open ``/dev/i2c-N`` (a :class:`~firmware_sim.pipuck.wire.Session`);
the thread serves them all with a selector, so transactions run one at a time, as on
the one physical bus.
"""

from __future__ import annotations

import selectors
import socket
import threading
from collections.abc import Callable

from firmware_sim.pipuck.wire import ProtocolError, Session

__all__ = ["SocketServer"]

THREAD_NAME = "ego-sim-pipuck"
SEND_TIMEOUT_S = 10.0


class SocketServer:
    """Listen on ``path`` and serve each connection with a Session from ``session``."""

    def __init__(self, path: str, session: Callable[[], Session]) -> None:
        self.path = path
        self._session = session
        self._listener = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
        self._listener.bind(path)
        self._listener.listen(64)
        self._listener.setblocking(False)
        self._wake_r, self._wake_w = socket.socketpair()
        self._selector = selectors.DefaultSelector()
        self._selector.register(self._listener, selectors.EVENT_READ, None)
        self._selector.register(self._wake_r, selectors.EVENT_READ, None)
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, name=THREAD_NAME)
        self._thread.start()

    def _run(self) -> None:
        try:
            while not self._stop.is_set():
                for key, _ in self._selector.select():
                    if key.fileobj is self._listener:
                        self._accept()
                    elif key.fileobj is not self._wake_r:
                        self._serve(key.fileobj, key.data)  # type: ignore[arg-type]
        finally:
            for key in list(self._selector.get_map().values()):
                if key.data is not None:
                    key.fileobj.close()  # type: ignore[union-attr]
            self._selector.close()

    def _accept(self) -> None:
        try:
            conn, _ = self._listener.accept()
        except BlockingIOError:
            return
        # A reply the client does not take within SEND_TIMEOUT_S drops the connection
        # (a stopped client must not keep the thread, and so close(), waiting).
        conn.settimeout(SEND_TIMEOUT_S)
        self._selector.register(conn, selectors.EVENT_READ, self._session())

    def _serve(self, conn: socket.socket, session: Session) -> None:
        try:
            data = conn.recv(65536)
            reply = session.feed(data) if data else None
            if reply:
                conn.sendall(reply)
        except (OSError, ProtocolError):
            reply = None
        if reply is None:
            self._selector.unregister(conn)
            conn.close()

    def close(self) -> None:
        """Stop the thread and join it; close every connection and the socket."""
        if self._stop.is_set():
            return
        self._stop.set()
        self._wake_w.send(b"x")
        self._thread.join()
        self._listener.close()
        self._wake_r.close()
        self._wake_w.close()
        if self._thread.is_alive():
            raise RuntimeError("the Pi-puck emulator's socket thread outlived close()")
