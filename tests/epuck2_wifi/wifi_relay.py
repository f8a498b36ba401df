"""A loopback TCP relay between ego and the emulated radio, for the tests: it counts the
bytes the robot sends, can cut every connection through it (a WiFi drop), can stop
passing the robot's bytes on (a link that goes deaf), and can stop accepting (the robot
out of reach)."""

from __future__ import annotations

import contextlib
import select
import socket
import threading


class Relay:
    """Listens on 127.0.0.1 (``address``) and joins each client to ``upstream``."""

    def __init__(self, upstream: tuple[str, int]) -> None:
        self.upstream = upstream
        self._server = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
        self._server.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        self._server.bind(("127.0.0.1", 0))
        self._server.listen(4)
        self.address: tuple[str, int] = self._server.getsockname()
        self.down_bytes = 0  # robot -> client
        self.accepted = 0
        self.passing = True  # pass the robot's bytes on
        self.accepting = True
        #: A radio that keeps dropping: cut each connection once the robot sent it this
        #: many bytes (None: never); ``drops`` counts those cuts.
        self.drop_after_bytes: int | None = None
        self.drops = 0
        self._sent_on: dict[socket.socket, int] = {}
        self._pairs: dict[socket.socket, socket.socket] = {}
        #: The relay's sockets to the robot (told apart without a syscall: cut() may close
        #: one under the pump).
        self._robot_side: set[socket.socket] = set()
        self._lock = threading.Lock()
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, name="epuck2-test-relay")
        self._thread.start()

    def cut(self) -> int:
        """Close every connection through the relay, both ends; how many were cut."""
        with self._lock:
            socks = list(self._pairs)
            self._pairs.clear()
        for sock in socks:
            with contextlib.suppress(OSError):
                sock.shutdown(socket.SHUT_RDWR)
            sock.close()
        return len(socks) // 2

    def close(self) -> None:
        self._stop.set()
        self._thread.join()
        self.cut()
        self._server.close()

    def _run(self) -> None:
        while not self._stop.is_set():
            with self._lock:
                socks = [self._server, *self._pairs]
            try:
                ready, _, _ = select.select(socks, [], [], 0.02)
            except (OSError, ValueError):
                continue  # a socket closed by cut() meanwhile
            for sock in ready:
                if sock is self._server:
                    self._accept()
                else:
                    self._pump(sock)

    def _accept(self) -> None:
        client, _ = self._server.accept()
        if not self.accepting:
            client.close()
            return
        self.accepted += 1
        robot = socket.create_connection(self.upstream)
        with self._lock:
            self._pairs[client] = robot
            self._pairs[robot] = client
            self._robot_side.add(robot)

    def _pump(self, sock: socket.socket) -> None:
        with self._lock:
            peer = self._pairs.get(sock)
        if peer is None:
            return
        try:
            data = sock.recv(65536)
        except OSError:
            data = b""
        from_robot = sock in self._robot_side
        if not data:
            self._drop(sock, peer)
            return
        if from_robot:
            self.down_bytes += len(data)
            if not self.passing:
                return
        with contextlib.suppress(OSError):
            peer.sendall(data)
        if from_robot and self.drop_after_bytes is not None:
            sent = self._sent_on.get(sock, 0) + len(data)
            self._sent_on[sock] = sent
            if sent >= self.drop_after_bytes:
                self.drops += 1
                self._drop(sock, peer)

    def _drop(self, sock: socket.socket, peer: socket.socket) -> None:
        with self._lock:
            self._pairs.pop(sock, None)
            self._pairs.pop(peer, None)
            self._robot_side.difference_update((sock, peer))
            self._sent_on.pop(sock, None)
            self._sent_on.pop(peer, None)
        for s in (sock, peer):
            with contextlib.suppress(OSError):
                s.shutdown(socket.SHUT_RDWR)
            s.close()
