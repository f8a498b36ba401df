"""One contract every Channel passes: the serial Link, RemoteChannel over TCP, UDP and a
Unix socket (with and without a shared secret), ZenohChannel over a loopback Zenoh
session, and ReplayChannel over a real recording.

A channel is what a Robot steps through (ego.seam.channel). Each factory below yields a channel
and the emulator behind it, whose world is the ground truth; a replay has no emulator (None):
it answers only the batches its run asked, so the tests of the whole contract
(``ALL_CHANNELS``) ask only :data:`READ` batches, and the tests that look at the emulator's
world run over the live channels (``CHANNELS``). To add a channel (a Bluetooth one, a
distributed engine's), add a factory to ``CHANNELS``.
"""

from __future__ import annotations

import contextlib
import dataclasses
import socket
import tempfile
import threading
import time
from collections.abc import Callable, Iterator
from functools import cache
from pathlib import Path

import pytest
import zenoh
from helpers import IN_PROCESS_LINK

from ego.backends.remote.channel import RemoteChannel
from ego.backends.zenoh_remote import ZenohChannel
from ego.core.registry import open_port
from ego.core.robot import Robot
from ego.core.safety import send_stop
from ego.errors import (
    LinkLostError,
    LinkTimeoutError,
    ProtocolError,
    ShortReplyError,
    UnsupportedDeviceError,
)
from ego.recording.writer import Recorder
from ego.seam.batch import Batch, Request
from ego.seam.channel import Channel, ChannelBase, TappedChannel
from ego.seam.profile import Command, Firmware, Profile
from ego.serial.link import Link
from ego.serial.profiles import PROFILES
from ego.serial.protocol import encode_batch
from ego.serial.transport import SerialTransport
from ego.servers.socket.server import Server
from ego.servers.socket.server_thread import ServerThread
from ego.servers.zenoh_node.node import RobotNode
from ego.zenoh_net.sessions import ZenohSettings, open_session
from firmware_sim import Emulator
from firmware_sim.ego_backend import EmulatorTruth

SECRET = "contract-secret-0123"
FAST = dataclasses.replace(IN_PROCESS_LINK, reconnect_timeout_s=0.5)
Factory = Callable[[str], contextlib.AbstractContextManager[tuple[Channel, Emulator]]]
AnyFactory = Callable[[str], contextlib.AbstractContextManager[tuple[Channel, Emulator | None]]]
#: How many READ batches a replay's recording holds: more than any one test asks.
RECORDED = 120


def read_batch(profile: Profile) -> Batch:
    """The batch the tests of the whole contract ask: it reads, and moves nothing."""
    return encode_batch([Request(Command.GET_SPEED), Request(Command.PROXIMITY)], profile)


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


def free_endpoint() -> str:
    """A Zenoh TCP endpoint on a loopback port free right now."""
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return f"tcp/127.0.0.1:{probe.getsockname()[1]}"


@contextlib.contextmanager
def zenoh_channel(firmware: str) -> Iterator[tuple[Channel, Emulator]]:
    """The robot node ``contract`` on its own loopback endpoint, and a controller's channel
    to it over a second session."""
    with contextlib.ExitStack() as stack:
        emu = stack.enter_context(Emulator(firmware, seed=1))
        link = Link(SerialTransport(emu.path), settings=FAST)
        stack.callback(link.close)
        endpoint = free_endpoint()
        served = open_session(ZenohSettings(listen=[endpoint], connect=[]))
        stack.callback(served.close)
        node = RobotNode(link, served, "contract", deadline_s=5.0,
                         world=EmulatorTruth(emu.world, emu)).start()
        stack.callback(node.close)
        mine = open_session(ZenohSettings(listen=[free_endpoint()], connect=[endpoint]))
        channel = ZenohChannel("contract", mine)  # it owns, and closes, its session
        stack.callback(channel.close)
        yield channel, emu


_RECORDINGS = tempfile.TemporaryDirectory(prefix="ego-contract-")


@cache
def recording_of(firmware: str) -> Path:
    """A real recording (ego.recording.writer) of a robot asked READ ``RECORDED`` times."""
    path = Path(_RECORDINGS.name) / f"{firmware}.mcap"
    with Emulator(firmware, seed=1) as emu, Robot(emu.path, link_settings=FAST) as robot:
        recorder = Recorder(path)
        recorder.attach(robot)
        try:
            for _ in range(RECORDED):
                robot.channel.exchange(read_batch(robot.channel.profile))
        finally:
            recorder.close()
    assert recorder.failure is None
    return path


@contextlib.contextmanager
def replay_channel(firmware: str) -> Iterator[tuple[Channel, None]]:
    opened = open_port(f"replay://{recording_of(firmware)}")
    channel = opened.channel
    try:
        yield channel, None
    finally:
        channel.close()


CHANNELS: dict[str, Factory] = {
    "serial": serial_link,
    "tcp": remote("tcp", None),
    "udp": remote("udp", None),
    "unix": remote("unix", None),
    "tcp sealed": remote("tcp", SECRET),
    "udp sealed": remote("udp", SECRET),
    "zenoh": zenoh_channel,
}
ALL_CHANNELS: dict[str, AnyFactory] = {**CHANNELS, "replay": replay_channel}


@pytest.fixture(params=list(CHANNELS))
def make(request: pytest.FixtureRequest) -> Factory:
    return CHANNELS[request.param]


@pytest.fixture(params=list(ALL_CHANNELS))
def make_any(request: pytest.FixtureRequest) -> AnyFactory:
    return ALL_CHANNELS[request.param]


# -- the whole contract: every channel, the replay's included ---------------------------------


def test_it_is_a_channel_built_on_the_base(make_any: AnyFactory) -> None:
    with make_any("webots") as (channel, _):
        assert isinstance(channel, Channel)
        assert isinstance(channel, ChannelBase)  # the lock, the checks, the counts: once
        assert channel.name


@pytest.mark.parametrize("firmware", ["webots", "gctronic"])
def test_it_says_the_firmware_it_speaks(make_any: AnyFactory, firmware: str) -> None:
    with make_any(firmware) as (channel, _):
        assert channel.info.firmware is Firmware(firmware)
        assert channel.profile == channel.info.profile


def test_stats_count_each_exchange_once(make_any: AnyFactory) -> None:
    with make_any("webots") as (channel, _):
        batch = read_batch(channel.profile)
        before = dataclasses.replace(channel.stats)
        for _ in range(3):
            assert len(channel.exchange(batch)) == batch.reply_size
        stats = channel.stats
        assert stats.batches - before.batches == 3
        assert stats.bytes_sent - before.bytes_sent == 3 * len(batch.tx)
        assert stats.bytes_received - before.bytes_received == 3 * batch.reply_size


def test_a_wrapper_forwards_and_counts_nothing_twice(make_any: AnyFactory) -> None:
    with make_any("webots") as (channel, _):
        seen: list[bytes] = []
        tapped = TappedChannel(channel, lambda batch, reply: seen.append(reply))
        batch = read_batch(tapped.profile)
        before = channel.stats.batches
        for _ in range(2):
            tapped.exchange(batch)
        assert tapped.stats is channel.stats and tapped.info is channel.info
        assert channel.stats.batches == before + 2 and len(seen) == 2
        assert tapped.name == channel.name


def test_a_reply_of_another_length_than_the_batch_asks_is_refused(make_any: AnyFactory) -> None:
    """A batch whose ``reply_size`` says two bytes more than its commands answer: the reply
    that comes is short of it, and no channel hands it over, nor counts it."""
    with make_any("webots") as (channel, _):
        batch = read_batch(channel.profile)
        lying = dataclasses.replace(batch, reply_size=batch.reply_size + 2)
        before = channel.stats.batches
        with pytest.raises((ShortReplyError, LinkTimeoutError)):  # a serial line times out
            channel.exchange(lying)
        assert channel.stats.batches == before
        assert len(channel.exchange(batch)) == batch.reply_size  # and it goes on


def test_two_threads_may_share_it(make_any: AnyFactory) -> None:
    """Each exchange is whole: no caller needs a lock of its own (50 replay steps each)."""
    with make_any("webots") as (channel, _):
        batch = read_batch(channel.profile)
        before = channel.stats.batches
        replies: list[bytes] = []
        errors: list[BaseException] = []
        start = threading.Barrier(2)

        def work() -> None:
            start.wait()
            try:
                for _ in range(50):
                    replies.append(channel.exchange(batch))
            except BaseException as exc:
                errors.append(exc)

        threads = [threading.Thread(target=work) for _ in range(2)]
        for thread in threads:
            thread.start()
        for thread in threads:
            thread.join()
        assert errors == []
        assert len(replies) == 100 and {len(r) for r in replies} == {batch.reply_size}
        for reply in replies:
            speeds, proximity = batch.decode(reply)
            assert speeds == (0, 0) and len(proximity) == 8
        assert channel.stats.batches == before + 100
        assert (channel.stats.retries, channel.stats.resyncs) == (0, 0)


def test_close_is_idempotent_and_final(make_any: AnyFactory) -> None:
    with make_any("webots") as (channel, _):
        channel.exchange(read_batch(channel.profile))
        channel.close()
        channel.close()
        with pytest.raises(LinkLostError):
            channel.exchange(read_batch(channel.profile))
        with pytest.raises(LinkLostError):
            channel.ascii_command("V", 2)


#: The threads a channel may start (a network channel's heartbeat, Zenoh's keepalive).
CHANNEL_THREADS = ("ego-remote-heartbeat", "ego-zenoh-keepalive")


def test_close_joins_every_thread_the_channel_started(make_any: AnyFactory) -> None:
    before = set(threading.enumerate())
    with make_any("webots") as (channel, _):
        channel.exchange(read_batch(channel.profile))
        channel.waiting_until(time.monotonic() + 1.0)  # a keepalive starts here, if any
        started = [t for t in set(threading.enumerate()) - before if t.name in CHANNEL_THREADS]
        channel.close()
        assert [t.name for t in started if t.is_alive()] == []


def test_a_channel_on_no_network_session_says_so(make_any: AnyFactory) -> None:
    with make_any("webots") as (channel, _):
        assert isinstance(channel, ChannelBase)
        found = channel.session_of(zenoh.Session)
        assert (found is not None) == isinstance(channel, ZenohChannel)
        assert TappedChannel(channel, lambda batch, reply: None).session_of(zenoh.Session) is found


# -- the live channels: what the emulator's world shows --------------------------------------


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
    with make("webots") as (channel, _):
        channel.waiting_until(time.monotonic() + 0.01)
        channel.close()
        channel.close()
        batch = encode_batch([Request(Command.GET_SPEED)], PROFILES[Firmware.WEBOTS])
        with pytest.raises(LinkLostError):
            channel.exchange(batch)
