"""UDP through a lossy relay: lost, duplicated, corrupted and reordered datagrams.

Whatever the network does, each step gets its own reply and runs on the robot once.
"""

from __future__ import annotations

import threading
import time

import pytest
from helpers import wait_until
from remote_helpers import ConnectFactory, DatagramProxy, FakeCamera, ServeFactory

from ego.backends.remote.channel import RemoteChannel
from ego.errors import LinkTimeoutError, PortNotFoundError
from ego.seam.batch import Request
from ego.seam.profile import Command
from ego.serial.link import LinkSettings
from ego.serial.protocol import encode_batch

#: The client link must not retry on its own here: a retry runs the batch again,
#: legitimately, and the test counts batches run.
NO_LINK_RETRY = LinkSettings(retries=0)
SECRET = b"udp handshake secret 0123456789"
LOSSY = {"drop": 0.15, "duplicate": 0.15, "reorder": 0.25, "corrupt": 0.05}


def test_no_step_gets_another_steps_reply_and_none_runs_twice(
    serve: ServeFactory, connect: ConnectFactory
) -> None:
    served = serve(kinds=("udp",))
    with DatagramProxy(served.url, seed=7, **LOSSY) as proxy:
        link = connect(
            proxy.url, settings=NO_LINK_RETRY, retransmit_s=0.01, retries=30, heartbeat=False
        )
        before = len(served.emu.history)
        steps = 100
        for i in range(steps):
            # Each step sets speeds of its own and reads them back in the same batch:
            # another step's reply would show another step's speeds.
            speed = i * 7 % 1000 - 500
            batch = encode_batch(
                [Request(Command.SET_SPEED, (speed, -speed)), Request(Command.GET_SPEED)],
                link.profile,
            )
            assert batch.decode(link.exchange(batch))[-1] == (speed, -speed), i
        ran = len(served.emu.history) - before
    stats = link.net  # type: ignore[attr-defined]
    assert served.server.stats.steps == steps  # each step's request ran once...
    # ... and its batch went to the robot once, but for the serial link's own retries
    # (a reply timeout on a loaded machine), which are not the network's doing.
    assert ran == steps + served.link.stats.retries
    # The relay did its worst, and both ends coped with it.
    assert proxy.counts["dropped"] and proxy.counts["duplicated"] and proxy.counts["delayed"]
    assert proxy.counts["corrupted"]
    assert stats.retransmits > 0
    assert stats.stale > 0  # late or doubled replies arrived, and were not taken
    assert served.server.stats.repeats > 0  # retransmissions answered from the cache


def test_big_replies_come_whole_and_in_order_over_a_lossy_network(
    serve: ServeFactory, connect: ConnectFactory
) -> None:
    camera = FakeCamera()
    served = serve(kinds=("udp",), frame_source=camera, chunk_size=4096)
    with DatagramProxy(served.url, seed=11, **LOSSY) as proxy:
        link = connect(proxy.url, retransmit_s=0.01, retries=30)
        source = link.frame_source()  # type: ignore[attr-defined]
        assert source.open(160, 120, "RGB565") == (160, 120, 320)
        for number in range(1, 6):
            assert source.read_frame() == camera.expected(number)  # 38,400 bytes, 10 slices
        source.close()
    assert camera.frames == 5  # a retransmitted request never grabbed another frame
    assert proxy.counts["dropped"]


def test_unanswered_step_fails_with_link_timeout_after_bounded_retransmissions(
    serve: ServeFactory,
) -> None:
    served = serve(kinds=("udp",))
    with DatagramProxy(served.url) as proxy:
        transport = RemoteChannel.from_url(
            proxy.url, retransmit_s=0.01, retries=3, heartbeat=False
        )
        try:
            link = transport
            proxy.drop = 1.0  # the network dies
            before = transport.net.retransmits
            start = time.monotonic()
            with pytest.raises(LinkTimeoutError, match="after 3 retransmissions"):
                link.exchange(encode_batch([Request(Command.PROXIMITY)], link.profile))
            elapsed = time.monotonic() - start
            assert transport.net.retransmits - before == 3
            assert elapsed < 0.5  # 10 + 20 + 40 + 80 ms, not the 5 s request timeout
        finally:
            proxy.drop = 0.0
            transport.close()


def test_slow_step_is_waited_for_not_run_again(
    serve: ServeFactory, connect: ConnectFactory
) -> None:
    """A request still running when its retransmission comes is acknowledged, not repeated."""
    served = serve(
        kinds=("udp",),
        emulator_options={"processing_delay_s": 0.03},
        link_settings=LinkSettings(reply_timeout_s=0.5),
    )
    link = connect(served.url, settings=NO_LINK_RETRY, retransmit_s=0.005, retries=2)
    before = len(served.emu.history)
    batch = encode_batch([Request(Command.PROXIMITY)] * 4, link.profile)
    link.exchange(batch)  # 150 ms of processing: far beyond 5 + 10 + 20 ms of retries
    assert len(served.emu.history) - before == 1
    assert link.net.retransmits >= 2  # type: ignore[attr-defined]


def test_the_handshake_is_retransmitted_until_the_connect_timeout_not_retries_times(
    serve: ServeFactory,
) -> None:
    """A server busy with a flood of HELLOs (or a network losing them) answers late: a
    client that asked to wait ``connect_timeout_s`` gets in within it, however many
    retransmissions that takes (issue 35: PortNotFoundError after 8, in under a second)."""
    served = serve(kinds=("udp",), secret=SECRET, require_secret=True)
    with DatagramProxy(served.url, drop=1.0) as proxy:  # every datagram lost, at first
        opened: list[RemoteChannel] = []
        failed: list[BaseException] = []

        def connect_now() -> None:
            try:
                opened.append(RemoteChannel.from_url(proxy.url, SECRET, retransmit_s=0.01,
                                                     retries=3, heartbeat=False,
                                                     connect_timeout_s=30.0))  # fmt: skip
            except BaseException as exc:  # the test's thread reports it
                failed.append(exc)

        client = threading.Thread(target=connect_now)
        client.start()
        try:
            # Beyond the step's three retransmissions, and still trying.
            assert wait_until(lambda: len(proxy.up) > 3 + 3 or failed)
            assert not failed, failed
            proxy.drop = 0.0  # the server's answers come through now
        finally:
            client.join(35)
        assert not failed, failed
        channel = opened[0]
        try:
            batch = encode_batch([Request(Command.GET_SPEED)], channel.profile)
            assert channel.exchange(batch) == bytes(4)
        finally:
            channel.close()


def test_a_silent_server_is_reported_once_the_connect_timeout_is_up(
    serve: ServeFactory,
) -> None:
    served = serve(kinds=("udp",), secret=SECRET, require_secret=True)
    with DatagramProxy(served.url, drop=1.0) as proxy:
        start = time.monotonic()
        with pytest.raises(PortNotFoundError, match="no ego server answers"):
            RemoteChannel.from_url(proxy.url, SECRET, retransmit_s=0.01, retries=3,
                                   heartbeat=False, connect_timeout_s=0.6)  # fmt: skip
        assert time.monotonic() - start >= 0.6  # it kept trying as long as it was told
        assert len(proxy.up) > 3 + 1
