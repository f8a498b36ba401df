"""Issue 24: the socket server and the Zenoh node are adapters of one control session
(the same events drive both to the same outcomes), and closing a node leaves no thread
of it behind. The node is real, on loopback Zenoh, with its clock handed in."""

from __future__ import annotations

import threading
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass

import pytest
from fakes import FAST_LINK
from helpers import wait_until
from zenoh_support import client_session, free_endpoint

from ego.backends.remote.connection import error_from_reply
from ego.net.frames import Frame, MessageType, decode_frame
from ego.net.handshake import ClientHandshake
from ego.net.messages import Ping, Step, pack_request
from ego.net.payloads import unpack_error
from ego.seam.batch import Request
from ego.seam.profile import Command
from ego.serial.link import Link
from ego.serial.protocol import encode_batch
from ego.serial.transport import SerialTransport
from ego.servers.sessions.actions import Action, Peer, Run, Send, StopRobot
from ego.servers.sessions.control import ControlSession
from ego.servers.sessions.session import Session
from ego.servers.zenoh_node.node import RobotNode
from ego.zenoh_net.sessions import ZenohSettings, open_session
from firmware_sim import Emulator

SPEEDS = (Request(Command.SET_SPEED, (300, 300)),)
#: (event, who, time): what both adapters are fed, in their own wire's terms.
SCRIPT = [
    ("drive", "a", 0.0),
    ("drive", "b", 0.1),
    ("keepalive", "a", 0.3),
    ("tick", "", 0.79),
    ("tick", "", 0.81),
]
EXPECTED = ["ok", "busy", "ok", "held by a", "stopped"]


class FakeClock:
    def __init__(self) -> None:
        self.now = 0.0

    def __call__(self) -> float:
        return self.now


class SocketAdapter:
    """``ego serve``'s session fed frames by hand (no secret: unsealed)."""

    def __init__(self) -> None:
        self.session = Session(secret=None, deadline_s=0.5, chunk_size=16384,
                               welcome=dict)  # fmt: skip
        self.peers = {who: Peer(("tcp", who, None), who, "127.0.0.1") for who in "ab"}
        self.sids: dict[str, int] = {}
        self.seq = 0

    @property
    def control(self) -> ControlSession[int]:
        return self.session.control

    def feed(self, who: str, mtype: MessageType, payload: bytes, now: float) -> list[Action]:
        self.seq += 1
        frame = Frame(mtype, self.seq, payload, self.sids.get(who, 0))
        return self.session.receive(self.peers[who], frame, now)

    def _connect(self, who: str, now: float) -> Frame:
        shake = ClientHandshake(None, who)
        (challenge,) = self.feed(who, MessageType.HELLO, shake.hello(), now)
        assert isinstance(challenge, Send)
        reply = decode_frame(challenge.data)
        if reply.type is MessageType.OK:
            self.sids[who] = reply.session
            *_, welcome = self.feed(who, MessageType.AUTH, shake.answer(reply.payload,
                                    reply.session), now)  # fmt: skip
            assert isinstance(welcome, Send)
            reply = decode_frame(welcome.data)
        return reply

    def _run(self, who: str, call: Step | Ping, now: float) -> str:
        (run,) = self.feed(who, *pack_request(call), now)
        assert isinstance(run, Run)
        (done,) = self.session.completed(run.session, run.seq, b"", now)
        return "ok" if isinstance(done, Send) else "lost"

    def drive(self, who: str, now: float) -> str:
        if who not in self.sids:
            reply = self._connect(who, now)
            if reply.type is MessageType.ERROR:
                name, _, _ = unpack_error(reply.payload)
                return "busy" if name == "RobotBusyError" else name
        return self._run(who, Step(SPEEDS), now)

    def keepalive(self, who: str, now: float) -> str:
        return self._run(who, Ping(), now)

    def tick(self, now: float) -> str:
        actions = self.session.tick(now)
        holder = self.session.controller
        if any(isinstance(a, StopRobot) for a in actions):
            return "stopped"
        return f"held by {holder.label}" if holder else "free"


@dataclass
class ZenohAdapter:
    """A Zenoh node on an emulator, its clock the test's, fed queries and puts."""

    node: RobotNode
    client: object
    clock: FakeClock

    @property
    def control(self) -> ControlSession[str]:
        return self.node.lease

    def drive(self, who: str, now: float) -> str:
        self.clock.now = now
        batch = encode_batch(SPEEDS, self.node.watched.profile)
        (reply,) = self.client.get("ego/n1/exchange", payload=batch.tx,  # type: ignore[attr-defined]
                                   attachment=who.encode(), timeout=2)  # fmt: skip
        if reply.ok is not None:
            return "ok"
        error = error_from_reply(reply.err.payload.to_bytes(), "node")
        return "busy" if "driven by another controller" in str(error) else str(error)

    def keepalive(self, who: str, now: float) -> str:
        self.clock.now = now
        self.client.put("ego/n1/keepalive", b"", attachment=who.encode())  # type: ignore[attr-defined]
        heard = wait_until(lambda: self.node.lease.last_heard == now, 2)
        return "ok" if heard else "unheard"

    def tick(self, now: float) -> str:
        lapses = self.node.lease.lapses
        self.clock.now = now
        # The fake clock jumps where a sleeping timer cannot see it: the deadman is told to
        # look now, and what it made of the time is known once it has looked.
        deadman = self.node.deadman
        assert deadman is not None
        looked = deadman.looked
        deadman.poke()
        assert wait_until(lambda: deadman.looked > looked), "the deadman never looked"
        if self.node.lease.lapses > lapses:
            assert wait_until(lambda: self.node.stops > 0), "the lapse never stopped the robot"
            return "stopped"
        holder = self.node.lease.holder
        return f"held by {holder}" if holder else "free"


@contextmanager
def zenoh_adapter() -> Iterator[ZenohAdapter]:
    clock = FakeClock()
    with Emulator("webots", seed=1) as emu:
        link = Link(SerialTransport(emu.path), settings=FAST_LINK)
        endpoint = free_endpoint()
        session = open_session(ZenohSettings(listen=[endpoint], connect=[]))
        node = RobotNode(link, session, "n1", deadline_s=0.5, clock=clock).start()
        client = client_session(endpoint)
        try:
            yield ZenohAdapter(node, client, clock)
        finally:
            client.close()
            node.close()
            session.close()
            link.close()


def play(adapter: SocketAdapter | ZenohAdapter) -> list[str]:
    outcomes = []
    for event, who, now in SCRIPT:
        if event == "tick":
            outcomes.append(adapter.tick(now))
        else:
            outcomes.append(getattr(adapter, event)(who, now))
    return outcomes


def test_the_socket_session_and_the_zenoh_node_run_the_one_control_session() -> None:
    socket = SocketAdapter()
    assert type(socket.control) is ControlSession
    assert play(socket) == EXPECTED
    assert socket.control.lapses == 1 and socket.control.holder is None
    with zenoh_adapter() as zenoh:
        assert type(zenoh.control) is ControlSession
        assert play(zenoh) == EXPECTED
        assert zenoh.control.lapses == 1 and zenoh.control.holder is None


def _ours(before: set[int | None]) -> list[threading.Thread]:
    # Zenoh's own (Rust) threads that ran a callback show up as dummies: not ours.
    return [t for t in threading.enumerate()
            if t.ident not in before and not isinstance(t, threading._DummyThread)]  # fmt: skip


@pytest.mark.parametrize("driven", [False, True])
def test_closing_a_node_leaves_no_thread_of_it_behind_and_none_was_a_daemon(driven: bool) -> None:
    with Emulator("webots", seed=1) as emu:
        link = Link(SerialTransport(emu.path), settings=FAST_LINK)
        endpoint = free_endpoint()
        session = open_session(ZenohSettings(listen=[endpoint], connect=[]))
        client = client_session(endpoint)
        try:
            before = {t.ident for t in threading.enumerate()}
            node = RobotNode(link, session, "n2", deadline_s=0.5).start()
            if driven:
                batch = encode_batch(SPEEDS, node.watched.profile)
                (reply,) = client.get("ego/n2/exchange", payload=batch.tx, attachment=b"a",
                                      timeout=2)  # fmt: skip
                assert reply.ok is not None
            serving = _ours(before)
            node.close()
            left = _ours(before)
        finally:
            client.close()
            session.close()
            link.close()
    names = sorted(t.name for t in serving)
    assert "ego-zenoh-deadman-n2" in names and "ego-zenoh-line-n2" in names, names
    assert [t.name for t in serving if t.daemon] == [], names
    assert [t.name for t in left] == []
