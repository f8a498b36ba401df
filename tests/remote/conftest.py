"""Fixtures of the remote tests: an emulator served by ``ego serve`` on loopback, and clients."""

from __future__ import annotations

import contextlib
import gc
from collections.abc import Iterator
from typing import Any

import pytest
from remote_helpers import ConnectFactory, Served, ServeFactory

from ego.backends.remote.channel import RemoteChannel
from ego.serial.link import Link, LinkSettings
from ego.serial.transport import SerialTransport
from ego.servers.socket.server import Server
from ego.servers.socket.server_thread import ServerThread
from firmware_sim import Emulator
from firmware_sim.camera import SimulatedSource

#: Client links fail fast in tests: the server's link already retried the serial line.
CLIENT_LINK = LinkSettings(retries=1, reconnect_timeout_s=2.0)
#: The served emulator's line: the emulator runs in the test's process, so on a loaded
#: machine its answer may wait for a core and for the GIL well past FAST_LINK's 10 ms, and
#: a retry would run a batch twice. The faults these tests inject (a 3 s stall, a reset)
#: are far longer, or need no timeout at all.
SERVED_LINK = LinkSettings(reply_timeout_s=0.25, reconnect_timeout_s=1.0, line_timeout_s=0.5)


@pytest.fixture
def serve() -> Iterator[ServeFactory]:
    """``serve(kinds=("tcp",), firmware="webots", **server_options)``: a served emulator.

    ``sim_camera=True`` serves the emulator's camera.
    """
    with contextlib.ExitStack() as stack:

        def factory(
            kinds: tuple[str, ...] = ("tcp",),
            firmware: str = "webots",
            emulator_options: dict[str, Any] | None = None,
            link_settings: LinkSettings = SERVED_LINK,
            sim_camera: bool = False,
            **options: Any,
        ) -> Served:
            emu = stack.enter_context(Emulator(firmware, seed=1, **(emulator_options or {})))
            link = Link(SerialTransport(emu.path), settings=link_settings)
            stack.callback(link.close)
            listen = [f"{kind}://127.0.0.1:0" for kind in kinds]
            if sim_camera:
                options["frame_source"] = SimulatedSource(emu.world)
            server = Server(link, listen=listen, **options)
            thread = stack.enter_context(ServerThread(server))
            return Served(emu, link, server, thread)

        yield factory


@pytest.fixture
def settled_heap() -> Iterator[None]:
    """A deadline measured without a full garbage collection of the whole test session's
    heap in the middle: the objects alive now (every earlier test's) are collected once
    and frozen out of the collector, and thawed after. In a full run that collection
    holds the GIL for a few hundred milliseconds on a loaded machine (a deadman measured
    0.3 s late in the suite, never alone); a robot's server never holds the thousands of
    tests' objects a suite run leaves to walk."""
    gc.collect()
    gc.freeze()
    try:
        yield
    finally:
        gc.unfreeze()


@pytest.fixture
def connect() -> Iterator[ConnectFactory]:
    """``connect(url, firmware=None, settings=CLIENT_LINK, **options)``: a RemoteChannel."""
    with contextlib.ExitStack() as stack:

        def factory(
            url: str,
            firmware: str | None = None,
            settings: LinkSettings = CLIENT_LINK,
            **options: Any,
        ) -> Link:
            channel = RemoteChannel.from_url(url, settings=settings, **options)
            stack.callback(channel.close)
            if firmware is not None:
                assert str(channel.info.firmware) == firmware
            return channel

        yield factory


@pytest.fixture(params=["tcp", "udp"])
def kind(request: pytest.FixtureRequest) -> str:
    """Each network test runs over TCP and over UDP."""
    return str(request.param)
