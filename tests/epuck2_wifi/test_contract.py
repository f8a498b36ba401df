"""The channel contract (tests/contract/test_channel_contract.py) for the WiFi channel, which
that suite's e-puck1 emulator cannot serve: built on the base, counted once, whole
exchanges from two threads, a lying batch refused, close idempotent, final, and joining
its reader thread; the safe stop confirmed through it."""

from __future__ import annotations

import dataclasses
import threading
from collections.abc import Iterator

import pytest
from helpers import wait_until

from ego.backends.epuck2.channel import Epuck2Channel
from ego.core.registry import open_port
from ego.core.safety import send_stop
from ego.errors import LinkLostError, ShortReplyError
from ego.seam.batch import Batch, Request
from ego.seam.channel import Channel, ChannelBase, TappedChannel
from ego.seam.profile import Command
from ego.serial.protocol import encode_batch
from firmware_sim.epuck2 import Epuck2Emulator


@pytest.fixture
def channel(url: str) -> Iterator[Epuck2Channel]:
    opened = open_port(url)
    assert isinstance(opened.channel, Epuck2Channel)
    yield opened.channel
    opened.close()


def read_batch(channel: Channel) -> Batch:
    return encode_batch([Request(Command.GET_SPEED), Request(Command.PROXIMITY)], channel.profile)


def test_it_is_a_channel_built_on_the_base(channel: Epuck2Channel) -> None:
    assert isinstance(channel, Channel) and isinstance(channel, ChannelBase)
    assert channel.info.selector == 15 and channel.profile is channel.info.profile


def test_stats_count_each_exchange_once_through_a_wrapper(channel: Epuck2Channel) -> None:
    batch = read_batch(channel)
    tapped = TappedChannel(channel, lambda b, r: None)
    before = dataclasses.replace(channel.stats)
    for _ in range(3):
        assert len(tapped.exchange(batch)) == batch.reply_size
    assert channel.stats.batches - before.batches == 3
    assert channel.stats.bytes_received - before.bytes_received == 3 * batch.reply_size


def test_a_lying_batch_is_refused_and_the_channel_goes_on(channel: Epuck2Channel) -> None:
    batch = read_batch(channel)
    with pytest.raises(ShortReplyError):
        channel.exchange(dataclasses.replace(batch, reply_size=batch.reply_size + 2))
    assert len(channel.exchange(batch)) == batch.reply_size


def test_two_threads_may_share_it(channel: Epuck2Channel) -> None:
    batch = read_batch(channel)
    replies: list[bytes] = []
    errors: list[BaseException] = []

    def work() -> None:
        try:
            for _ in range(10):
                replies.append(channel.exchange(batch))
        except BaseException as exc:
            errors.append(exc)

    threads = [threading.Thread(target=work) for _ in range(2)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert errors == [] and len(replies) == 20
    assert all(batch.decode(r)[0] == (0, 0) for r in replies)


def test_close_is_idempotent_final_and_joins_its_reader(url: str) -> None:
    channel = open_port(url).channel
    channel.exchange(read_batch(channel))
    assert any(t.name == "epuck2-wifi-reader" for t in threading.enumerate())
    channel.close()
    channel.close()
    assert not any(t.name == "epuck2-wifi-reader" for t in threading.enumerate())
    with pytest.raises(LinkLostError):
        channel.exchange(read_batch(channel))


def test_the_safe_stop_is_confirmed_through_it(
    wifi: Epuck2Emulator, channel: Epuck2Channel
) -> None:
    set_speed = encode_batch([Request(Command.SET_SPEED, (300, 300))], channel.profile)
    channel.exchange(set_speed)
    assert wait_until(lambda: wifi.world.speeds == (300, 300))
    send_stop(channel)
    assert channel.exchange(read_batch(channel))[:4] == bytes(4)
    assert wait_until(lambda: wifi.world.speeds == (0, 0))
