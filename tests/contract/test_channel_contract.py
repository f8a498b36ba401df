"""One contract every Channel passes: the serial Link, and RemoteChannel over TCP, UDP and a
Unix socket, with and without a shared secret.

A channel is what a Robot steps through (ego.core.channel). Each factory below yields a channel
to an emulated dsPIC, and the emulator, whose world is the ground truth. To add a channel
(a Bluetooth one, a distributed engine's), add a factory to ``CHANNELS``.
"""

from __future__ import annotations

import contextlib
import tempfile
from collections.abc import Callable, Iterator
from pathlib import Path

import pytest

from ego.backends.remote.channel import RemoteChannel
from ego.core.channel import Channel
from ego.core.safety import send_stop
from ego.errors import LinkLostError, ProtocolError, UnsupportedDeviceError
from ego.serial.link import Link, LinkSettings
from ego.serial.protocol import PROFILES, Command, Firmware, Request, encode_batch
from ego.serial.transport import SerialTransport
from ego.servers.socket.server import Server, ServerThread
from firmware_sim import Emulator

SECRET = "contract-secret-0123"
FAST = LinkSettings(resync_quiet_s=0.02, reconnect_timeout_s=0.5)
Factory = Callable[[str], contextlib.AbstractContextManager[tuple[Channel, Emulator]]]


@contextlib.contextmanager
def serial_link(firmware: str) -> Iterator[tuple[Channel, Emulator]]:
    with Emulator(firmware, seed=1) as emu:
        link = Link(SerialTransport(emu.path), settings=FAST)
        try:
            yield link, emu
        finally:
            link.close()


def remote(kind: str, secret: str | None) -> Factory:
    @contextlib.contextmanager
    def factory(firmware: str) -> Iterator[tuple[Channel, Emulator]]:
        with (
            Emulator(firmware, seed=1) as emu,
            tempfile.TemporaryDirectory() as folder,
            contextlib.closing(Link(SerialTransport(emu.path), settings=FAST)) as link,
        ):
            listen = f"unix://{Path(folder) / 's'}" if kind == "unix" else f"{kind}://127.0.0.1:0"
            with ServerThread(Server(link, listen=listen, secret=secret)) as served:
                channel = RemoteChannel.from_url(served.url, secret, settings=FAST)
                try:
                    yield channel, emu
                finally:
                    channel.close()

    return factory


CHANNELS: dict[str, Factory] = {
    "serial": serial_link,
    "tcp": remote("tcp", None),
    "udp": remote("udp", None),
    "unix": remote("unix", None),
    "tcp sealed": remote("tcp", SECRET),
    "udp sealed": remote("udp", SECRET),
}


@pytest.fixture(params=list(CHANNELS))
def make(request: pytest.FixtureRequest) -> Factory:
    return CHANNELS[request.param]


def test_it_is_a_channel(make: Factory) -> None:
    with make("webots") as (channel, _):
        assert isinstance(channel, Channel)
        assert channel.name


@pytest.mark.parametrize("firmware", ["webots", "gctronic"])
def test_it_knows_the_firmware_and_its_exact_profile(make: Factory, firmware: str) -> None:
    with make(firmware) as (channel, _):
        assert channel.info.firmware is Firmware(firmware)
        assert channel.profile == channel.info.profile
        assert channel.profile.commands == PROFILES[Firmware(firmware)].commands


def test_exchange_returns_exactly_the_reply_of_the_batch(make: Factory) -> None:
    with make("webots") as (channel, emu):
        batch = encode_batch(
            [Request(Command.SET_SPEED, (120, -80)), Request(Command.GET_SPEED),
             Request(Command.PROXIMITY)],
            channel.profile,
        )  # fmt: skip
        reply = channel.exchange(batch)
        assert len(reply) == batch.reply_size
        _, speeds, proximity = batch.decode(reply)
        assert speeds == (120, -80)
        assert len(proximity) == 8
        assert emu.world.speeds == (120, -80)


def test_a_batch_without_reply_returns_nothing(make: Factory) -> None:
    with make("webots") as (channel, _):
        batch = encode_batch([Request(Command.SET_SPEED, (50, 50))], channel.profile)
        assert channel.exchange(batch) == b""
        confirm = encode_batch([Request(Command.GET_SPEED)], channel.profile)
        assert confirm.decode(channel.exchange(confirm)) == [(50, 50)]


def test_ascii_version_answers_its_lines(make: Factory) -> None:
    with make("webots") as (channel, _):
        lines = channel.ascii_command("V", 2)
        assert lines[0].startswith("v,")
        assert len(lines) == 2


def test_calibration_waits_for_its_last_line(make: Factory) -> None:
    with make("webots") as (channel, _):
        lines = channel.calibrate_proximity()
        assert "finished" in lines[-1]


def test_a_batch_the_firmware_cannot_serve_is_refused(make: Factory) -> None:
    with make("gctronic") as (channel, emu):
        before = len(emu.history)
        webots = PROFILES[Firmware.WEBOTS]  # M is Webots' only
        with pytest.raises((UnsupportedDeviceError, ProtocolError)):
            channel.exchange(encode_batch([Request(Command.FLOOR)], webots))
        assert len(emu.history) == before


def test_the_safe_stop_is_confirmed_through_it(make: Factory) -> None:
    with make("webots") as (channel, emu):
        channel.exchange(encode_batch([Request(Command.SET_SPEED, (300, 300))], channel.profile))
        send_stop(channel)
        assert emu.world.speeds == (0, 0)


def test_waiting_is_harmless_and_close_is_idempotent(make: Factory) -> None:
    import time

    with make("webots") as (channel, _):
        channel.waiting_until(time.monotonic() + 0.01)
        channel.close()
        channel.close()
        batch = encode_batch([Request(Command.GET_SPEED)], PROFILES[Firmware.WEBOTS])
        with pytest.raises(LinkLostError):
            channel.exchange(batch)
