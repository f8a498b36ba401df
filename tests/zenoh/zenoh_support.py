"""Robots served as Zenoh nodes on loopback, for the Zenoh tests."""

from __future__ import annotations

import socket
import sys
from collections.abc import Iterator
from contextlib import ExitStack, contextmanager
from dataclasses import dataclass
from typing import Any

from fakes import FAST_LINK
from helpers import REPOSITORY, spawn

from ego.serial.link import Link, LinkSettings
from ego.serial.transport import SerialTransport
from ego.servers.zenoh_node.node import RobotNode
from ego.zenoh_net.sessions import ZenohSettings, open_session
from firmware_sim import Emulator
from firmware_sim.ego_backend import EmulatorTruth
from firmware_sim.scene import Scene


def free_endpoint() -> str:
    """A Zenoh TCP endpoint on a loopback port free right now."""
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return f"tcp/127.0.0.1:{probe.getsockname()[1]}"


@dataclass
class Node:
    emulator: Emulator
    node: RobotNode
    endpoint: str

    @property
    def world(self) -> Any:
        return self.emulator.world


@contextmanager
def served_node(
    name: str = "epuck", deadline_s: float = 0.5, settings: LinkSettings = FAST_LINK,
    scene: bool = False, **emulator: Any,
) -> Iterator[Node]:  # fmt: skip
    """An emulated robot served as the Zenoh node ``name``, listening on its own endpoint
    (its serial link quick to recover, unless ``settings`` says otherwise); with
    ``scene``, its world's scene served too (as ego swarm's nodes serve theirs)."""
    with ExitStack() as stack:
        emu = stack.enter_context(Emulator("webots", seed=1, **emulator))
        link = Link(SerialTransport(emu.path), settings=settings)
        stack.callback(link.close)
        endpoint = free_endpoint()
        session = open_session(ZenohSettings(listen=[endpoint], connect=[]))
        stack.callback(session.close)
        node = RobotNode(link, session, name, deadline_s=deadline_s,
                         world=EmulatorTruth(emu.world, emu),
                         scene=Scene(emu.world) if scene else None).start()
        stack.callback(node.close)
        yield Node(emu, node, endpoint)


@dataclass
class NodeApart:
    node: RobotNode
    endpoint: str


@contextmanager
def served_node_apart(name: str, deadline_s: float, settings: LinkSettings) -> Iterator[NodeApart]:
    """The Zenoh node ``name`` serving an emulated robot whose dsPIC runs in a process of
    its own (``python -m firmware_sim``), as a robot's does: a flood at the node then
    competes for the node's interpreter, not the dsPIC's. What the robot did is known
    from the node's side only (its confirmed stops, :attr:`RobotNode.stops`)."""
    with ExitStack() as stack:
        emulator = stack.enter_context(
            spawn([sys.executable, "-m", "firmware_sim", "--seed", "1"], REPOSITORY)
        )
        assert emulator.stdout is not None
        path = emulator.stdout.readline().strip()
        assert path, "the emulator printed no pty path"
        link = Link(SerialTransport(path), settings=settings)
        stack.callback(link.close)
        endpoint = free_endpoint()
        session = open_session(ZenohSettings(listen=[endpoint], connect=[]))
        stack.callback(session.close)
        node = RobotNode(link, session, name, deadline_s=deadline_s).start()
        stack.callback(node.close)
        yield NodeApart(node, endpoint)


def client_session(endpoint: str) -> Any:
    """A peer session that reaches ``endpoint`` (and listens on loopback only)."""
    return open_session(ZenohSettings(listen=[free_endpoint()], connect=[endpoint]))
