"""Webots' radio (Emitter, Receiver) over Zenoh: packets between robots, and between a
robot and a PC, on ``ego/radio/CHANNEL`` (keys.py).

A packet is the bytes sent, with an attachment saying who sent it, the emitter's range
and, when the sender knows it (an emulated robot: its world's true pose), where it was.
A receiver drops packets from its own robot, and, when both poses are known, packets
from beyond the emitter's range; it computes Webots' signal strength (1 / distance²) and
the emitter's direction in its own frame from the two poses. Where a pose is unknown (a
real robot has no ground truth) both are NaN: documented as unavailable.

Sans-I/O where it can be: :class:`Packet` and :func:`received` take bytes and poses and
return what the receiver sees; :class:`Radio` only puts and subscribes.
"""

from __future__ import annotations

import dataclasses
import json
import math
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from ego.zenoh_net.keys import BROADCAST, radio_key, radio_keys

if TYPE_CHECKING:
    import zenoh

__all__ = ["INFINITE_RANGE", "Packet", "Radio", "received"]

#: Webots' range -1: no limit.
INFINITE_RANGE = -1.0
_NAN3 = (math.nan, math.nan, math.nan)

Pose = list[float] | tuple[float, float, float]


@dataclass(frozen=True)
class Packet:
    """One received packet, as a Receiver serves it."""

    data: bytes
    sender: str
    channel: int
    signal_strength: float
    direction: tuple[float, float, float]
    #: When it arrived (time.time()): what a latency measurement compares its send with.
    arrived_s: float = 0.0


def attachment(sender: str, emitter_range: float, pose: Pose | None) -> bytes:
    """What an emitted packet carries beside its data."""
    return json.dumps({"from": sender, "range": emitter_range,
                       "pose": list(pose) if pose is not None else None}).encode()  # fmt: skip


def received(
    data: bytes, meta: bytes | None, channel: int, me: str, my_pose: Pose | None
) -> Packet | None:
    """What a receiver named ``me`` at ``my_pose`` makes of a packet (None: not for it)."""
    try:
        info = json.loads(meta or b"{}")
        sender = str(info["from"])
        emitter_range = float(info.get("range", INFINITE_RANGE))
        pose = info.get("pose")
    except (ValueError, KeyError, TypeError):
        return None  # not an ego radio packet
    if sender == me:
        return None
    if pose is None or my_pose is None:
        return Packet(data, sender, channel, math.nan, _NAN3)
    dx, dy = float(pose[0]) - my_pose[0], float(pose[1]) - my_pose[1]
    distance = math.hypot(dx, dy)
    if emitter_range >= 0 and distance > emitter_range:
        return None
    strength = 1.0 / distance**2 if distance > 0 else math.inf
    # The emitter's direction in the receiver's frame (x forward, y left, z up).
    c, s = math.cos(my_pose[2]), math.sin(my_pose[2])
    norm = distance or 1.0
    direction = ((c * dx + s * dy) / norm, (c * dy - s * dx) / norm, 0.0)
    return Packet(data, sender, channel, strength, direction)


class Radio:
    """A robot's radio on a Zenoh session: puts for its Emitter, a subscription for its
    Receiver. ``pose`` gives the robot's true pose when known (else None)."""

    def __init__(
        self,
        session: zenoh.Session,
        me: str,
        pose: Callable[[], Pose | None],
        *,
        owns_session: bool = False,
    ) -> None:
        self.session = session
        self.me = me
        self.pose = pose
        self._owns_session = owns_session
        self._subscribers: list[Any] = []
        self._lock = threading.Lock()
        self._incoming: list[Packet] = []

    def send(self, channel: int, data: bytes, emitter_range: float) -> None:
        self.session.put(radio_key(channel), data,
                         attachment=attachment(self.me, emitter_range, self.pose()))  # fmt: skip

    def listen(self, channel: int) -> None:
        """Receive on ``channel`` (BROADCAST: every channel) from now on."""
        self.stop_listening()
        for key in radio_keys(channel):
            self._subscribers.append(self.session.declare_subscriber(key, self._arrived))

    def stop_listening(self) -> None:
        while self._subscribers:
            self._subscribers.pop().undeclare()

    def _arrived(self, sample: Any) -> None:
        key = str(sample.key_expr)
        tail = key.rsplit("/", 1)[-1]
        channel = BROADCAST if tail == "all" else int(tail) if tail.lstrip("-").isdigit() else 0
        meta = sample.attachment.to_bytes() if sample.attachment is not None else None
        packet = received(sample.payload.to_bytes(), meta, channel, self.me, self.pose())
        if packet is not None:
            packet = dataclasses.replace(packet, arrived_s=time.time())
            with self._lock:
                self._incoming.append(packet)

    def take(self) -> list[Packet]:
        """The packets that arrived since the last call (the receiver's step)."""
        with self._lock:
            packets, self._incoming = self._incoming, []
        return packets

    def close(self) -> None:
        self.stop_listening()
        if self._owns_session:
            self.session.close()
