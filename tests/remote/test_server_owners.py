"""Issue 24 item 8, ``ego serve``'s side: a stop never closes the camera source under a
read, and closing a server leaves no thread of it behind (and none of its threads is a
daemon, killed mid-work at exit). Real sockets on loopback, a slow source injected."""

from __future__ import annotations

import contextlib
import threading
from collections.abc import Iterator

from fakes import FAST_LINK
from helpers import wait_until
from remote_helpers import RawClient

from ego.camera.source import GrantedFormat, PixelFormat
from ego.net.frames import MessageType
from ego.net.messages import CameraFrame, CameraOpen, Step, pack_request
from ego.seam.batch import Request
from ego.seam.profile import Command
from ego.serial.link import Link
from ego.serial.transport import SerialTransport
from ego.servers.service import RobotService
from ego.servers.socket.server import Server
from ego.servers.socket.server_thread import ServerThread
from firmware_sim import Emulator


class SlowSource:
    """A frame source whose ``read_frame`` waits until the test lets it go, and which
    notes a close that came while a read was under way."""

    def __init__(self) -> None:
        self.reading = threading.Event()
        self.go = threading.Event()
        self.inside = False
        self.closed = 0
        self.closed_while_reading = 0

    def open(self, width: int, height: int, pixel_format: str) -> GrantedFormat:
        return GrantedFormat(width, height, 2 * width)

    def read_frame(self) -> bytes:
        self.inside = True
        self.reading.set()
        try:
            assert self.go.wait(5)
            return bytes(8 * 8 * 2)
        finally:
            self.inside = False

    def set_control(self, name: str, value: int) -> int:
        return value

    def close(self) -> None:
        self.closed += 1
        self.closed_while_reading += self.inside


@contextlib.contextmanager
def emulated_link() -> Iterator[Link]:
    with Emulator("webots", seed=1) as emu:
        link = Link(SerialTransport(emu.path), settings=FAST_LINK)
        try:
            yield link
        finally:
            link.close()


def test_a_stop_from_another_thread_waits_for_the_read_in_hand_to_close_the_camera() -> None:
    source = SlowSource()
    with emulated_link() as link:
        service = RobotService(link, source)  # type: ignore[arg-type]
        service.run(CameraOpen(8, 8, PixelFormat.YUYV.value))
        reader = threading.Thread(target=service.run, args=(CameraFrame("raw"),))
        reader.start()
        try:
            assert source.reading.wait(5)
            service.stop(close_camera=True)  # the deadman's thread: wheels stopped at once
            assert source.closed == 0  # ... but the camera is another thread's just now
        finally:
            source.go.set()
            reader.join(5)
    assert source.closed == 1 and source.closed_while_reading == 0


def test_a_goodbye_during_a_frame_closes_the_camera_only_once_the_frame_is_read() -> None:
    source = SlowSource()
    with emulated_link() as link, ServerThread(
        Server(link, listen="tcp://127.0.0.1:0", frame_source=source)  # type: ignore[arg-type]
    ) as running:
        client = RawClient(running.url)
        try:
            assert client.handshake().type is MessageType.OK
            client.send(*pack_request(CameraOpen(8, 8, PixelFormat.YUYV.value)))
            assert client.receive().type is MessageType.OK
            client.send(*pack_request(CameraFrame("raw")))
            assert source.reading.wait(5)
            client.send(MessageType.BYE)  # a stop with the camera's close, while it reads
            assert wait_until(lambda: running.server.controller is None, 5)
            assert running.server.service.channel.lock.acquire(timeout=5)  # the stop ran
            running.server.service.channel.lock.release()
            assert source.closed_while_reading == 0
        finally:
            source.go.set()
            client.close()
        assert wait_until(lambda: source.closed == 1, 5)
    assert source.closed_while_reading == 0


def _ours(before: set[int]) -> list[threading.Thread]:
    return [t for t in threading.enumerate() if t.ident not in before]


def test_closing_a_server_leaves_no_thread_of_it_behind_and_none_was_a_daemon() -> None:
    source = SlowSource()
    source.go.set()
    with emulated_link() as link:
        before = {t.ident for t in threading.enumerate()}
        server = Server(link, listen=["tcp://127.0.0.1:0", "udp://127.0.0.1:0"],
                        frame_source=source)  # type: ignore[arg-type]  # fmt: skip
        with ServerThread(server) as running:
            client = RawClient(running.url)
            try:
                assert client.handshake().type is MessageType.OK
                step = Step((Request(Command.SET_SPEED, (100, 100)),))
                for call in (step, CameraOpen(8, 8, PixelFormat.YUYV.value), CameraFrame("raw")):
                    client.send(*pack_request(call))
                    assert client.receive().type is MessageType.OK
                serving = _ours(before)  # the loop, the deadman, the workers
            finally:
                client.close()
        left = _ours(before)
    names = sorted(t.name for t in serving)
    assert {"ego-serve", "ego-serve-deadman"} <= set(names), names
    assert [t.name for t in serving if t.daemon] == [], names
    assert [t.name for t in left] == []
