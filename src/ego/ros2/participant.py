"""A ROS 2 node on a Zenoh session, as rmw_zenoh makes one: its tokens, publishers and
subscriptions (the I/O side of :mod:`ego.ros2`; the formats stay in their own modules).

A :class:`Participant` declares the node's liveliness token (``ros2 node list``), and
one per publisher and subscription (``ros2 topic list``, ``ros2 topic info``) while it
is open; :meth:`Participant.close` undeclares every one of them. A :class:`Publisher`
puts each message on its topic's exact key with the 33-byte attachment (its own
sequence number from 1, the time, and the GID rmw_zenoh derives from its token); a
:class:`Subscription` takes samples on the exact key, drops those without an attachment
(as rmw_zenoh's subscription does) and hands the decoded message on.

Zenoh's threads never run Python for a subscription: its samples wait in a bounded ring
inside Zenoh (the newest kept, :func:`ring_capacity`), and a thread of the
subscription's own decodes them and calls the callback. So a flood on one topic neither
holds Zenoh's network threads on Python's GIL (where it would delay every other topic,
another robot's cmd_vel included) nor queues without end. What it drops is counted by
reason (:attr:`Subscription.refused`) and logged once, then summarised every 10 s.

Usage::

    with Participant(session, "epuck", namespace="/robot", distro="jazzy") as node:
        ps0 = node.publisher("ps0", "sensor_msgs/msg/Range", SENSOR_DATA)
        ps0.publish(message)
        node.subscription("cmd_vel", "geometry_msgs/msg/Twist", QoS(depth=1), on_twist)
"""

from __future__ import annotations

import itertools
import logging
import threading
import time
from collections.abc import Callable
from functools import cache
from types import TracebackType
from typing import Any

from ego.errors import EgoError, FrameError, ThreadLeakError
from ego.nursery import Nursery
from ego.ros2.attachment import Attachment, decode_attachment, encode_attachment
from ego.ros2.distros import Distro, distro_format
from ego.ros2.gid import entity_gid
from ego.ros2.keys import topic_key
from ego.ros2.liveliness import NodeInfo, TopicInfo, node_token, publisher_token, subscription_token
from ego.ros2.messages import decode_message, encode_message, message_class, type_hash
from ego.ros2.names import node_namespace, resolve_topic
from ego.ros2.qos import QoS
from ego.zenoh_net.tally import Tally

__all__ = ["Participant", "Publisher", "Subscription", "ring_capacity"]

log = logging.getLogger(__name__)

#: rmw_zenoh numbers nodes and entities from one counter a context (jazzy
#: src/detail/rmw_context_impl_s.cpp:129-131); ego uses one for the whole process, so
#: two participants on one session never share an id.
_IDS = itertools.count()
_IDS_LOCK = threading.Lock()


def _next_id() -> int:
    with _IDS_LOCK:
        return next(_IDS)


#: The fewest samples a subscription's ring keeps (a depth-1 topic too: one slow decode
#: must not lose the Twist behind a burst of malformed ones), and the most.
MIN_RING, MAX_RING = 64, 1024
#: A subscription's thread offers the GIL after this many samples in a row.
YIELD_EVERY = 16


def ring_capacity(qos: QoS) -> int:
    """How many samples a subscription of ``qos`` keeps waiting for its thread."""
    return max(MIN_RING, min(MAX_RING, int(qos.depth or 0)))


@cache
def _hash(type_name: str, distro: Distro) -> str:
    return type_hash(type_name, distro)


class Publisher:
    """One topic's publisher: its key, token, GID and sequence number."""

    def __init__(self, node: Participant, topic: str, type_name: str, qos: QoS) -> None:
        self.topic, self.type_name, self.distro = topic, type_name, node.distro
        type_hash_ = _hash(type_name, node.distro)
        self.key = topic_key(node.info.domain_id, topic, type_name, type_hash_, node.distro)
        self.token_key = publisher_token(
            node.info, _next_id(), TopicInfo(topic, type_name, type_hash_, qos), node.distro
        )
        self.gid = entity_gid(self.token_key, node.distro)
        self.cls: Any = message_class(type_name, node.distro)
        self.sequence = 0
        self._lock = threading.Lock()
        self._publisher = node.session.declare_publisher(self.key)
        self._token = node.session.liveliness().declare_token(self.token_key)

    @property
    def matched(self) -> bool:
        """Whether a subscriber on the key is known (epuck_ros2's camera publishes only
        then: ``get_subscription_count() > 0``)."""
        return bool(self._publisher.matching_status.matching)

    def publish(self, message: Any, stamp_ns: int | None = None) -> None:
        """Put ``message`` (a :attr:`cls` instance, or another of the same type)."""
        self.publish_payload(encode_message(message, self.distro), stamp_ns)

    def publish_payload(self, payload: bytes, stamp_ns: int | None = None) -> None:
        """Put an already encoded payload, with the next attachment."""
        with self._lock:
            self.sequence += 1
            attachment = Attachment(self.sequence, stamp_ns or time.time_ns(), self.gid)
            self._publisher.put(payload, attachment=encode_attachment(attachment, self.distro))

    def close(self) -> None:
        self._token.undeclare()
        self._publisher.undeclare()


class Subscription:
    """One topic's subscription: decoded messages to ``callback(message, attachment)``, on
    a thread of its own (see the module's doc)."""

    def __init__(
        self, node: Participant, topic: str, type_name: str, qos: QoS,
        callback: Callable[[Any, Attachment], None],
    ) -> None:  # fmt: skip
        import zenoh

        self.topic, self.type_name, self.distro = topic, type_name, node.distro
        type_hash_ = _hash(type_name, node.distro)
        self.key = topic_key(node.info.domain_id, topic, type_name, type_hash_, node.distro)
        self.token_key = subscription_token(
            node.info, _next_id(), TopicInfo(topic, type_name, type_hash_, qos), node.distro
        )
        self.callback = callback
        #: Samples dropped, by reason: "no attachment" (as rmw_zenoh drops them),
        #: "malformed" (not decodable), "callback" (the callback raised).
        self.refused = Tally(log, f"{topic}: sample dropped")
        self._subscriber = node.session.declare_subscriber(
            self.key, zenoh.handlers.RingChannel(ring_capacity(qos))
        )
        # The handler, not the subscriber: its recv() ends when the subscriber goes.
        self._samples = self._subscriber.handler
        self._thread = node.nursery.start_thread(self._run, name=f"ego-ros2-sub {topic}")
        try:
            self._token = node.session.liveliness().declare_token(self.token_key)
        except BaseException:
            self._end()
            raise

    @property
    def dropped(self) -> int:
        """How many samples were dropped, for any reason."""
        return self.refused.total

    def _run(self) -> None:
        for taken in itertools.count(1):
            try:
                sample = self._samples.recv()
            except Exception as exc:  # zenoh.ZError: the subscriber is undeclared
                log.debug("%s: no more samples (%s)", self.topic, exc)
                return
            self._take(sample)
            if taken % YIELD_EVERY == 0:
                # Under a flood this thread always has work: offer the GIL now and then,
                # so that the steps and the deadman never wait a switch interval for it.
                time.sleep(0)

    def _take(self, sample: Any) -> None:
        if sample.attachment is None:  # rmw_subscription_data.cpp:221-228
            self.refused.add("no attachment", "rmw_zenoh drops a sample without one")
            return
        try:
            attachment = decode_attachment(sample.attachment.to_bytes(), self.distro)
            message = decode_message(sample.payload.to_bytes(), self.type_name, self.distro)
        except FrameError as exc:
            self.refused.add("malformed", str(exc))
            return
        try:
            self.callback(message, attachment)
        except Exception as exc:  # a bug in the callback: counted, the topic stays served
            self.refused.add("callback", f"{type(exc).__name__}: {exc}")

    def _end(self) -> None:
        self._subscriber.undeclare()
        if self._thread is not threading.current_thread():
            self._thread.join(5)
            if self._thread.is_alive():
                raise ThreadLeakError(f"{self._thread.name}: still running 5 s after close")

    def close(self) -> None:
        self._token.undeclare()
        self._end()


class Participant:
    """A ROS 2 node ``name`` in ``namespace`` on ``session`` (see the module's doc)."""

    def __init__(
        self, session: Any, name: str, *, namespace: str = "/", domain_id: int = 0,
        distro: Distro | str = Distro.JAZZY,
    ) -> None:  # fmt: skip
        self.session = session
        distro_format(distro)  # an unknown name says so, listing the known ones
        self.distro = Distro(distro)
        zid = str(session.info.zid())
        self.info = NodeInfo(domain_id, zid, _next_id(), name, node_namespace(namespace))
        node_key = node_token(self.info, self.distro)  # checks every field first
        self._entities: list[Publisher | Subscription] = []
        self._token = session.liveliness().declare_token(node_key)
        self._closed = False
        #: The subscriptions' threads; a program that exits with the node open has it
        #: closed first (their samples end), before Python waits for them.
        self.nursery = Nursery(f"ego-ros2-node {name}", at_exit=self.close)

    def resolve(self, topic: str) -> str:
        """``topic`` fully qualified in this node's namespace (``ps0`` -> ``/robot/ps0``)."""
        return resolve_topic(topic, self.info.namespace, self.info.name)

    def publisher(self, topic: str, type_name: str, qos: QoS) -> Publisher:
        """A publisher of ``type_name`` on ``topic`` (resolved in the namespace)."""
        self._check_open()
        made = Publisher(self, self.resolve(topic), type_name, qos)
        self._entities.append(made)
        return made

    def subscription(
        self, topic: str, type_name: str, qos: QoS, callback: Callable[[Any, Attachment], None]
    ) -> Subscription:
        """A subscription to ``topic`` (resolved in the namespace) calling ``callback``."""
        self._check_open()
        made = Subscription(self, self.resolve(topic), type_name, qos, callback)
        self._entities.append(made)
        return made

    def withdraw(self, entity: Publisher | Subscription) -> None:
        """Undeclare one publisher or subscription of this node (and its token)."""
        if entity in self._entities:
            self._entities.remove(entity)
            entity.close()

    def _check_open(self) -> None:
        if self._closed:
            raise EgoError(f"ROS 2 node {self.info.name} is closed")

    @property
    def token_keys(self) -> list[str]:
        """Every liveliness token this node declares now, its own first."""
        if self._closed:
            return []
        return [node_token(self.info, self.distro), *(e.token_key for e in self._entities)]

    def close(self) -> None:
        """Undeclare every publisher, subscription and token; again does nothing."""
        if self._closed:
            return
        self._closed = True
        while self._entities:
            self._entities.pop().close()
        self._token.undeclare()
        self.nursery.close()

    def __enter__(self) -> Participant:
        return self

    def __exit__(
        self, exc_type: type[BaseException] | None, exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:  # fmt: skip
        self.close()
