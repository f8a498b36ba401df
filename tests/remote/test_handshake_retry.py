"""A client whose connection is cut during its handshake connects again (issue 24's
flood tests found it): a server under a flood of half-open connections hangs up the
oldest to make room, and a real client may be that one. The cut here is a relay that
resets the first connection it carries once the client's HELLO arrives."""

from __future__ import annotations

import contextlib
import socket
import struct
import threading

import pytest
from remote_helpers import ServeFactory

from ego.backends.remote.channel import RemoteChannel
from ego.errors import PortNotFoundError
from ego.seam.batch import Request
from ego.seam.profile import Command
from ego.serial.protocol import encode_batch

SECRET = b"handshake retry secret 0123456789"


class CuttingRelay:
    """Resets the first ``cuts`` connections after their first bytes; relays the rest."""

    def __init__(self, target: tuple[str, int], cuts: int) -> None:
        self.target = target
        self.cuts = cuts
        self.cut = 0
        self.listener = socket.create_server(("127.0.0.1", 0))
        self._threads = [threading.Thread(target=self._accept)]
        self._socks: list[socket.socket] = [self.listener]
        self._threads[0].start()

    @property
    def url(self) -> str:
        return f"tcp://127.0.0.1:{self.listener.getsockname()[1]}"

    def _accept(self) -> None:
        while True:
            try:
                client, _ = self.listener.accept()
            except OSError:
                return
            self._socks.append(client)
            if self.cut < self.cuts:
                self.cut += 1
                client.recv(1 << 16)  # the HELLO, then a reset (RST, not FIN)
                client.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, struct.pack("ii", 1, 0))
                client.close()
                continue
            server = socket.create_connection(self.target)
            self._socks.append(server)
            for a, b in ((client, server), (server, client)):
                pump = threading.Thread(target=self._pump, args=(a, b))
                pump.start()
                self._threads.append(pump)

    @staticmethod
    def _pump(source: socket.socket, sink: socket.socket) -> None:
        with contextlib.suppress(OSError):  # a side closed: the relay ends
            while data := source.recv(1 << 16):
                sink.sendall(data)
        for sock in (source, sink):
            with contextlib.suppress(OSError):  # already shut by the other pump
                sock.shutdown(socket.SHUT_RDWR)

    def close(self) -> None:
        """Wake the accepting thread (closing a listening socket alone does not, on
        Linux), close every socket, and join every thread."""
        with contextlib.suppress(OSError):
            self.listener.shutdown(socket.SHUT_RDWR)
        for sock in self._socks:
            sock.close()
        for thread in self._threads:
            thread.join(5)
            assert not thread.is_alive(), f"{thread.name} outlived the relay"


def _relay(served_url: str, cuts: int) -> CuttingRelay:
    host, port = served_url.removeprefix("tcp://").rsplit(":", 1)
    return CuttingRelay((host, int(port)), cuts)


def test_a_handshake_cut_by_the_server_is_tried_again_on_a_new_connection(
    serve: ServeFactory,
) -> None:
    served = serve(kinds=("tcp",), secret=SECRET, require_secret=True)
    relay = _relay(served.url, cuts=2)
    try:
        channel = RemoteChannel.from_url(relay.url, SECRET, heartbeat=False)
        try:
            batch = encode_batch([Request(Command.GET_SPEED)], channel.profile)
            assert channel.exchange(batch) == bytes(4)
        finally:
            channel.close()
        assert relay.cut == 2
    finally:
        relay.close()


def test_a_server_that_always_cuts_is_reported_once_the_time_is_up(serve: ServeFactory) -> None:
    served = serve(kinds=("tcp",), secret=SECRET, require_secret=True)
    relay = _relay(served.url, cuts=10**6)
    try:
        with pytest.raises(PortNotFoundError, match="no ego server"):
            RemoteChannel.from_url(relay.url, SECRET, heartbeat=False, connect_timeout_s=0.5)
        assert relay.cut > 1  # it tried again, and then gave up
    finally:
        relay.close()
