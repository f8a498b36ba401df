"""Webots' radio (Emitter, Receiver) over Zenoh: packets between robots, and between a
robot and a PC, on ``ego/radio/CHANNEL`` (keys.py).

A packet is the bytes sent, with an attachment saying who sent it, the emitter's range
and, when the sender knows it (an emulated robot: its world's true pose), where it was.
A receiver drops packets from its own robot, and, when both poses are known, packets
from beyond the emitter's range; it computes Webots' signal strength (1 / distance²) and
the emitter's direction in its own frame from the two poses. Where a pose is unknown (a
real robot has no ground truth) both are NaN: documented as unavailable. A pose that is
not finite (NaN, inf) is unknown too, and never passes a range check: a packet of an
emitter with a limited range is then dropped. A packet with no attachment (``z_put``
from Zenoh's tools) comes from an unknown sender, ``""``.

A packet whose attachment is malformed (not JSON, no sender, a range or a pose that is
not a number, a pose farther than :data:`MAX_POSE_M` from the origin on an axis: 1e308
overflowed the signal strength, issue 32) is dropped, counted and logged (one line, then
a summary every 10 s), never raised in Zenoh's thread. The receiving buffer is bounded,
as Webots' Receiver's ``bufferSize``: at most :data:`BUFFER_PACKETS` packets and
:data:`BUFFER_BYTES` bytes of data wait; packets arriving while it is full are dropped and
counted (Webots: "data may be lost").

Sans-I/O where it can be: :class:`Packet` and :func:`received` take bytes and poses and
return what the receiver sees; :class:`Radio` only puts and subscribes.
"""

from __future__ import annotations

import dataclasses
import json
import logging
import math
import threading
import time
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from ego.errors import FrameError
from ego.zenoh_net.keys import BROADCAST, radio_key, radio_keys
from ego.zenoh_net.tally import Tally

if TYPE_CHECKING:
    import zenoh

__all__ = ["BUFFER_BYTES", "BUFFER_PACKETS", "INFINITE_RANGE", "Packet", "Radio", "received"]

log = logging.getLogger(__name__)

#: Webots' range -1: no limit.
INFINITE_RANGE = -1.0
#: The receiving buffer's bound, in packets and in bytes of data (Webots' Receiver has a
#: ``bufferSize``, -1 for no limit in its PROTO; a network radio needs a bound): a
#: controller that reads every step never comes near it.
BUFFER_PACKETS = 1024
BUFFER_BYTES = 1 << 20
#: The longest attachment (sender, range, pose) read; the longest sender name.
MAX_ATTACHMENT_BYTES = 1024
MAX_SENDER_CHARS = 256
#: The farthest a finite pose's x or y may be, in metres (a robot's world is metres
#: across; 1000 km keeps 1 / distance² and the direction well within a float).
MAX_POSE_M = 1e6
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


def _is_number(value: object) -> bool:
    return isinstance(value, int | float) and not isinstance(value, bool)


def _pose(value: object, whose: str) -> tuple[float, float, float] | None:
    """A pose [x_m, y_m, theta_rad]; None if unknown or not finite; FrameError if not one."""
    if value is None:
        return None
    if not (isinstance(value, list | tuple) and len(value) == 3 and all(map(_is_number, value))):
        raise FrameError(f"radio packet from {whose!r}: pose {str(value)[:60]} is not "
                         "[x_m, y_m, theta_rad]")  # fmt: skip
    x, y, theta = (float(v) for v in value)
    if not all(map(math.isfinite, (x, y, theta))):
        return None
    if abs(x) > MAX_POSE_M or abs(y) > MAX_POSE_M:
        raise FrameError(f"radio packet from {whose!r}: pose ({x:g}, {y:g}) is beyond "
                         f"{MAX_POSE_M:g} m of the origin")  # fmt: skip
    return (x, y, theta)


def _header(meta: bytes | None) -> tuple[str, float, Any]:
    """The sender, the emitter's range and the raw pose an attachment carries."""
    if meta is None:
        return "", INFINITE_RANGE, None  # a plain put (z_put): an unknown sender
    if len(meta) > MAX_ATTACHMENT_BYTES:
        raise FrameError(f"radio packet attachment of {len(meta)} bytes "
                         f"(at most {MAX_ATTACHMENT_BYTES})")  # fmt: skip
    try:
        info = json.loads(meta)
    except (ValueError, RecursionError) as exc:
        raise FrameError(f"radio packet attachment is not JSON: {exc}") from exc
    sender = info.get("from") if isinstance(info, dict) else None
    if not isinstance(sender, str) or len(sender) > MAX_SENDER_CHARS:
        raise FrameError(f"radio packet attachment {meta[:60]!r} names no sender ('from': "
                         f"a string of at most {MAX_SENDER_CHARS} characters)")  # fmt: skip
    emitter_range = info.get("range", INFINITE_RANGE)
    if not _is_number(emitter_range) or not (emitter_range == -1 or emitter_range >= 0):
        raise FrameError(f"radio packet from {sender!r}: range {emitter_range!r} is not "
                         "-1 (no limit) or a number >= 0")  # fmt: skip
    return sender, float(emitter_range), info.get("pose")


def received(
    data: bytes, meta: bytes | None, channel: int, me: str, my_pose: Pose | None
) -> Packet | None:
    """What a receiver named ``me`` at ``my_pose`` makes of a packet: None if not for it
    (its own, from beyond the emitter's range); FrameError if malformed."""
    sender, emitter_range, raw_pose = _header(meta)
    if sender == me:
        return None
    pose = _pose(raw_pose, sender)
    mine = _pose(my_pose, "this robot")
    if pose is None or mine is None:
        given = (raw_pose is not None and pose is None) or (my_pose is not None and mine is None)
        if given and emitter_range >= 0:
            return None  # a pose given but not finite: the distance is unknown, never in range
        return Packet(data, sender, channel, math.nan, _NAN3)
    dx, dy = pose[0] - mine[0], pose[1] - mine[1]
    distance = math.hypot(dx, dy)
    if emitter_range >= 0 and distance > emitter_range:
        return None
    strength = 1.0 / distance**2 if distance > 0 else math.inf
    # The emitter's direction in the receiver's frame (x forward, y left, z up).
    c, s = math.cos(mine[2]), math.sin(mine[2])
    norm = distance or 1.0
    direction = ((c * dx + s * dy) / norm, (c * dy - s * dx) / norm, 0.0)
    return Packet(data, sender, channel, strength, direction)


def channel_of(key: str) -> int:
    """The channel of a radio key ``ego/radio/C`` (``all``: BROADCAST); FrameError if none."""
    tail = key.rsplit("/", 1)[-1]
    if tail == "all":
        return BROADCAST
    if tail.isascii() and tail.isdigit() and len(tail) <= 9:
        return int(tail)
    raise FrameError(f"radio key {key[:80]!r} names no channel")


class Radio:
    """A robot's radio on a Zenoh session: puts for its Emitter, a subscription for its
    Receiver, whose buffer holds at most ``buffer_packets`` packets and ``buffer_bytes``
    bytes of data. ``pose`` gives the robot's true pose when known (else None)."""

    def __init__(
        self,
        session: zenoh.Session,
        me: str,
        pose: Callable[[], Pose | None],
        *,
        owns_session: bool = False,
        buffer_packets: int = BUFFER_PACKETS,
        buffer_bytes: int = BUFFER_BYTES,
    ) -> None:
        self.session = session
        self.me = me
        self.pose = pose
        self.buffer_packets = buffer_packets
        self.buffer_bytes = buffer_bytes
        self._owns_session = owns_session
        self._subscribers: list[Any] = []
        self._lock = threading.Lock()
        self._incoming: deque[Packet] = deque()
        self._incoming_bytes = 0
        #: What was dropped, by reason: "full" (the buffer), "malformed".
        self.dropped = Tally(log, f"radio of {me}: dropped a packet")

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

    def fits(self, queued: int, queued_bytes: int, size: int) -> bool:
        """Whether a packet of ``size`` bytes fits beside ``queued`` ones (the bound)."""
        return queued < self.buffer_packets and queued_bytes + size <= self.buffer_bytes

    def _arrived(self, sample: Any) -> None:
        data = sample.payload.to_bytes()
        with self._lock:  # full: dropped before anything is parsed (a flood's cost)
            full = not self.fits(len(self._incoming), self._incoming_bytes, len(data))
        if full:
            self.dropped.add("full", f"{self.buffer_packets} packets or {self.buffer_bytes} "
                             "bytes wait already")  # fmt: skip
            return
        meta = sample.attachment.to_bytes() if sample.attachment is not None else None
        try:
            channel = channel_of(str(sample.key_expr))
            packet = received(data, meta, channel, self.me, self.pose())
        except FrameError as exc:
            self.dropped.add("malformed", str(exc))
            return
        if packet is not None:
            packet = dataclasses.replace(packet, arrived_s=time.time())
            with self._lock:
                self._incoming.append(packet)
                self._incoming_bytes += len(data)

    def take(self) -> list[Packet]:
        """The packets that arrived since the last call (the receiver's step)."""
        with self._lock:
            packets, self._incoming = list(self._incoming), deque()
            self._incoming_bytes = 0
        return packets

    def close(self) -> None:
        self.stop_listening()
        if self._owns_session:
            self.session.close()
