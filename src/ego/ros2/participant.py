"""A ROS 2 node on a Zenoh session, as rmw_zenoh makes one: its tokens, publishers and
subscriptions (the I/O side of :mod:`ego.ros2`; the formats stay in their own modules).

A :class:`Participant` declares the node's liveliness token (``ros2 node list``), and
one per publisher and subscription (``ros2 topic list``, ``ros2 topic info``) while it
is open; :meth:`Participant.close` undeclares every one of them. A :class:`Publisher`
puts each message on its topic's exact key with the 33-byte attachment (its own
sequence number from 1, the time, and the GID rmw_zenoh derives from its token); a
:class:`Subscription` takes samples on the exact key, drops those without an attachment
(as rmw_zenoh's subscription does) and hands the decoded message on. The callbacks run
on Zenoh's own threads, which the session owns.

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

from ego.errors import EgoError, FrameError
from ego.ros2.attachment import Attachment, decode_attachment, encode_attachment
from ego.ros2.distros import Distro, distro_format
from ego.ros2.gid import entity_gid
from ego.ros2.keys import topic_key
from ego.ros2.liveliness import NodeInfo, TopicInfo, node_token, publisher_token, subscription_token
from ego.ros2.messages import decode_message, encode_message, message_class, type_hash
from ego.ros2.names import node_namespace, resolve_topic
from ego.ros2.qos import QoS

__all__ = ["Participant", "Publisher", "Subscription"]

log = logging.getLogger(__name__)

#: rmw_zenoh numbers nodes and entities from one counter a context (jazzy
#: src/detail/rmw_context_impl_s.cpp:129-131); ego uses one for the whole process, so
#: two participants on one session never share an id.
_IDS = itertools.count()
_IDS_LOCK = threading.Lock()


def _next_id() -> int:
    with _IDS_LOCK:
        return next(_IDS)


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
    """One topic's subscription: decoded messages to ``callback(message, attachment)``."""

    def __init__(
        self, node: Participant, topic: str, type_name: str, qos: QoS,
        callback: Callable[[Any, Attachment], None],
    ) -> None:  # fmt: skip
        self.topic, self.type_name, self.distro = topic, type_name, node.distro
        type_hash_ = _hash(type_name, node.distro)
        self.key = topic_key(node.info.domain_id, topic, type_name, type_hash_, node.distro)
        self.token_key = subscription_token(
            node.info, _next_id(), TopicInfo(topic, type_name, type_hash_, qos), node.distro
        )
        self.callback = callback
        #: Samples dropped: no attachment (as rmw_zenoh drops them), or not decodable.
        self.dropped = 0
        self._subscriber = node.session.declare_subscriber(self.key, self._on_sample)
        self._token = node.session.liveliness().declare_token(self.token_key)

    def _on_sample(self, sample: Any) -> None:
        if sample.attachment is None:  # rmw_subscription_data.cpp:221-228
            self.dropped += 1
            return
        try:
            attachment = decode_attachment(sample.attachment.to_bytes(), self.distro)
            message = decode_message(sample.payload.to_bytes(), self.type_name, self.distro)
        except FrameError as exc:
            self.dropped += 1
            log.warning("%s: sample dropped: %s", self.topic, exc)
            return
        self.callback(message, attachment)

    def close(self) -> None:
        self._token.undeclare()
        self._subscriber.undeclare()


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

    def __enter__(self) -> Participant:
        return self

    def __exit__(
        self, exc_type: type[BaseException] | None, exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:  # fmt: skip
        self.close()
