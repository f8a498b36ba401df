"""A RemoteChannel: the emulator served by ``ego serve``, driven over TCP and UDP."""

from __future__ import annotations

import time

import pytest
from fakes import FAST_LINK
from helpers import wait_until
from remote_helpers import ConnectFactory, ServeFactory

from ego.backends.remote.channel import RemoteChannel
from ego.core.registry import open_port
from ego.errors import (
    FrameError,
    LinkTimeoutError,
    PortNotFoundError,
    ProtocolError,
    RobotResetError,
    UnsupportedDeviceError,
)
from ego.net.frames import MessageType
from ego.seam.batch import Batch, Request
from ego.seam.profile import Command, Firmware
from ego.serial.link import Link
from ego.serial.profiles import PROFILES
from ego.serial.protocol import encode_batch
from ego.serial.transport import SerialTransport
from ego.servers.socket.server import Server
from ego.servers.socket.server_thread import ServerThread
from firmware_sim import Emulator, FaultTimings

#: The thesis' full sensor batch: a E M N O Q u.
SENSORS = (
    Command.ACCELEROMETER_RAW,
    Command.GET_SPEED,
    Command.FLOOR,
    Command.PROXIMITY,
    Command.LIGHT,
    Command.GET_STEPS,
    Command.MIC_AMPLITUDE,
)


def test_full_sensor_batch_reply_is_the_dspics_reply(
    serve: ServeFactory, connect: ConnectFactory, kind: str
) -> None:
    served = serve(kinds=(kind,))
    link = connect(served.url)
    batch = encode_batch([Request(c) for c in SENSORS], link.profile)
    for _ in range(5):
        reply = link.exchange(batch)
        assert reply == served.emu.history[-1].reply  # byte for byte what the dsPIC sent
        assert served.emu.history[-1].commands == "aEMNOQu"
    assert len(batch.decode(reply)) == len(SENSORS)


def test_actuator_batch_moves_the_emulated_wheels_and_leds(
    serve: ServeFactory, connect: ConnectFactory, kind: str
) -> None:
    served = serve(kinds=(kind,))
    link = connect(served.url)
    requests = [Request(Command.SET_SPEED, (300, -200)), Request(Command.SET_LED, (3, 1))]
    assert link.exchange(encode_batch(requests, link.profile)) == b""
    # The dsPIC hears the batch once its bytes crossed the emulated wire.
    assert wait_until(lambda: served.emu.world.speeds == (300, -200))
    assert wait_until(lambda: served.emu.world.leds[3] == 1)


def test_firmware_is_detected_through_the_relay(
    serve: ServeFactory, connect: ConnectFactory, kind: str
) -> None:
    served = serve(kinds=(kind,), firmware="gctronic")
    link = connect(served.url)
    assert link.profile.firmware is Firmware.GCTRONIC  # from the relayed V and C
    assert str(link.info.firmware) == "gctronic"
    batch = encode_batch([Request(Command.PROXIMITY)], link.profile)
    assert len(batch.decode(link.exchange(batch))[0]) == 10  # ps0..ps7 + IR8, IR9


def test_ascii_command_is_relayed(serve: ServeFactory, connect: ConnectFactory, kind: str) -> None:
    served = serve(kinds=(kind,), firmware="gctronic")
    link = connect(served.url)
    assert link.ascii_command("C") == ["c,10"]
    assert link.ascii_command("V", lines=2)[0].startswith("v,Version 1.2.2")
    link.exchange(encode_batch([Request(Command.SET_SPEED, (500, 500))], link.profile))
    assert link.ascii_command("S") == ["s"]
    assert served.emu.world.speeds == (0, 0)  # S stopped it before answering


def test_unrelayed_ascii_command_is_refused(serve: ServeFactory, connect: ConnectFactory) -> None:
    link = connect(serve().url)
    with pytest.raises(ProtocolError, match="'R' is not relayed"):
        link.ascii_command("R")


def test_batch_the_server_firmware_cannot_serve_is_refused(
    serve: ServeFactory, connect: ConnectFactory, kind: str
) -> None:
    served = serve(kinds=(kind,), firmware="gctronic")
    link = connect(served.url)
    before = len(served.emu.history)
    webots = PROFILES[Firmware.WEBOTS]  # a batch made for another firmware: M exists there
    with pytest.raises(UnsupportedDeviceError, match="floor"):
        link.exchange(encode_batch([Request(Command.FLOOR)], webots))
    assert len(served.emu.history) == before  # nothing reached the robot
    batch = encode_batch([Request(Command.GET_SPEED)], link.profile)
    assert link.exchange(batch) == bytes(4)  # and the session goes on


@pytest.mark.parametrize(
    ("garbage", "error"),
    [
        (b"", FrameError),
        (b"\xb2", FrameError),
        (b"\xbc\x02\x01\x00\x00\x00", FrameError),
        (b"\xff\x00", FrameError),
        (b"\x00\x00", FrameError),
        (b"\x9e\x00", UnsupportedDeviceError),
        (b"\xbc\x01\x01\x00\x00\x00", ProtocolError),
    ],
    ids=[
        "empty",
        "count cut",
        "arguments cut",
        "unknown command",
        "end byte",
        "not on this firmware",
        "wrong arity",
    ],
)
def test_malformed_step_is_refused_before_the_robot(
    serve: ServeFactory, connect: ConnectFactory, garbage: bytes, error: type[Exception]
) -> None:
    served = serve()
    link = connect(served.url)
    before = len(served.emu.history)
    with pytest.raises(error):
        link._conn.call(MessageType.STEP, garbage)  # type: ignore[union-attr]
    assert len(served.emu.history) == before
    batch = encode_batch([Request(Command.GET_STEPS)], link.profile)
    assert len(link.exchange(batch)) == 4


def test_serial_timeout_on_the_robot_comes_back_as_link_timeout(
    serve: ServeFactory, connect: ConnectFactory, kind: str
) -> None:
    served = serve(kinds=(kind,), emulator_options={"timings": FaultTimings(stall_s=3.0)})
    link = connect(served.url)
    served.emu.inject("stall")
    with pytest.raises(LinkTimeoutError, match="reply bytes"):
        link.exchange(encode_batch([Request(Command.PROXIMITY)], link.profile))


def test_robot_restart_comes_back_as_robot_reset(
    serve: ServeFactory, connect: ConnectFactory, kind: str
) -> None:
    served = serve(kinds=(kind,))
    link = connect(served.url)
    batch = encode_batch([Request(Command.PROXIMITY)], link.profile)
    link.exchange(batch)
    served.emu.inject("reset")
    with pytest.raises(RobotResetError, match="restarted"):
        link.exchange(batch)
    assert len(batch.decode(link.exchange(batch))[0]) == 8  # the next step works


def test_network_urls_go_to_the_remote_backend(serve: ServeFactory, kind: str) -> None:
    served = serve(kinds=(kind,))
    transport = open_port(served.url).channel
    try:
        assert isinstance(transport, RemoteChannel)
        assert transport.name == served.url
    finally:
        transport.close()


def test_no_server_is_port_not_found(kind: str) -> None:
    start = time.monotonic()
    with pytest.raises(PortNotFoundError, match=r"127\.0\.0\.1:9"):
        RemoteChannel.from_url(f"{kind}://127.0.0.1:9", connect_timeout_s=0.3)
    assert time.monotonic() - start < 2.0


def test_client_close_is_idempotent_and_stops_the_robot(
    serve: ServeFactory, connect: ConnectFactory, kind: str
) -> None:
    served = serve(kinds=(kind,))
    link = connect(served.url)
    link.exchange(encode_batch([Request(Command.SET_SPEED, (200, 200))], link.profile))
    link.close()
    link.close()
    assert served.emu.world.speeds == (0, 0)  # the goodbye stopped it at once
    assert served.server.controller is None


class SlowStop:
    """A served robot's channel whose stop batch reaches the line 100 ms late (a busy
    serial line, a loaded machine): injected, as hardware is."""

    def __init__(self, inner: Link, delay_s: float = 0.1) -> None:
        self.inner = inner
        self.delay_s = delay_s

    def exchange(self, batch: Batch) -> bytes:
        if batch.requests and batch.requests[0] == Request(Command.SET_SPEED, (0, 0)):
            time.sleep(self.delay_s)
        return self.inner.exchange(batch)

    def __getattr__(self, name: str) -> object:
        return getattr(self.inner, name)


def test_close_over_udp_returns_only_once_the_robot_stands_still() -> None:
    """The goodbye's stop outlasts the client's retransmission timer: its repeated BYE
    must not be told OK before the robot stopped."""
    with Emulator("webots", seed=1) as emu:
        link = Link(SerialTransport(emu.path), settings=FAST_LINK)
        try:
            server = Server(SlowStop(link), listen="udp://127.0.0.1:0")  # type: ignore[arg-type]
            with ServerThread(server) as running:
                client = RemoteChannel.from_url(running.url, retransmit_s=0.005, heartbeat=False)
                go = [Request(Command.SET_SPEED, (200, 200)), Request(Command.GET_SPEED)]
                client.exchange(encode_batch(go, client.profile))
                assert emu.world.speeds == (200, 200)
                client.close()
                assert emu.world.speeds == (0, 0)  # stopped before close() returned
        finally:
            link.close()
