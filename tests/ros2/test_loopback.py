"""A real Zenoh exchange on loopback: ego's keys, payload, attachment and liveliness token
on one side, a subscriber written the way rmw_zenoh's subscription is on the other.

The subscriber follows jazzy ros2-gbp/rmw_zenoh-release@d38ea19c
src/detail/rmw_subscription_data.cpp: an advanced subscriber on the exact topic key
(:168, :239-244), which drops a sample that has no attachment (:221-228) and reads the
attachment with zenoh-ext's deserializer (src/detail/attachment_helpers.cpp:77-82); it
reads the payload with this folder's own CDR reader, not ego's. The graph side queries
``@ros2_lv/<domain>/**`` as the graph cache does (liveliness_utils.cpp:428-432).
"""

from __future__ import annotations

import threading
import time
from collections.abc import Iterator
from contextlib import ExitStack
from typing import Any

import pytest
from helpers import wait_until
from ros2_support import CdrReader, free_endpoint
from zenoh.ext import Int64, declare_advanced_subscriber, z_deserialize

from ego.ros2 import (
    SENSOR_DATA,
    Attachment,
    EntityKind,
    NodeInfo,
    TopicInfo,
    encode_attachment,
    graph_key,
    parse_token,
    publisher_token,
    topic_key,
)
from ego.ros2.gid import entity_gid
from ego.ros2.messages import encode_message, message_class, type_hash
from ego.zenoh_net.sessions import ZenohSettings, open_session

RANGE = "sensor_msgs/msg/Range"


class RmwStyleSubscription:
    """What rmw_zenoh's SubscriptionData does with a sample, minus the ROS types."""

    def __init__(self, session: Any, key: str) -> None:
        self.lock = threading.Lock()
        self.received: list[tuple[int, int, bytes, float]] = []
        self.dropped = 0
        self.sub = declare_advanced_subscriber(session, key, self.on_sample)

    def on_sample(self, sample: Any) -> None:
        if sample.attachment is None:  # "Unable to obtain attachment": dropped
            with self.lock:
                self.dropped += 1
            return
        seq, stamp, gid = z_deserialize(tuple[Int64, Int64, bytes], sample.attachment)
        reader = CdrReader(sample.payload.to_bytes())
        reader.read("int32"), reader.read("uint32"), reader.string(), reader.read("uint8")
        range_m = [reader.read("float32") for _ in range(4)][-1]
        with self.lock:
            self.received.append((seq, stamp, gid, range_m))


@pytest.fixture
def sessions() -> Iterator[tuple[Any, Any]]:
    """Two peer sessions on 127.0.0.1: the subscriber's listens, the publisher's connects."""
    with ExitStack() as stack:
        endpoint = free_endpoint()
        subscriber = open_session(ZenohSettings(listen=[endpoint], connect=[]))
        stack.callback(subscriber.close)
        publisher = open_session(ZenohSettings(listen=[free_endpoint()], connect=[endpoint]))
        stack.callback(publisher.close)
        yield publisher, subscriber


def _range_message(distro: str, value: float) -> Any:
    stamp = message_class("builtin_interfaces/msg/Time", distro)(sec=5, nanosec=0)
    header = message_class("std_msgs/msg/Header", distro)(stamp=stamp, frame_id="ps0")
    return message_class(RANGE, distro)(
        header=header, radiation_type=1, field_of_view=0.5, min_range=0.0, max_range=0.25,
        range=value, variance=0.0,
    )  # fmt: skip


@pytest.mark.parametrize("distro", ["jazzy", "kilted"])
def test_an_rmw_style_subscriber_takes_egos_samples_and_sees_its_token(
    sessions: tuple[Any, Any], distro: str
) -> None:
    pub_session, sub_session = sessions
    hash_ = type_hash(RANGE, distro)
    key = topic_key(0, "/robot/ps0", RANGE, hash_, distro)
    # The subscriber spells its key out, as TopicInfo's constructor does (:86-93).
    subscription = RmwStyleSubscription(
        sub_session, f"0/robot/ps0/sensor_msgs::msg::dds_::Range_/{hash_}"
    )
    node = NodeInfo(0, str(pub_session.info.zid()), 0, "epuck", namespace="/robot")
    token_key = publisher_token(node, 1, TopicInfo("/robot/ps0", RANGE, hash_, SENSOR_DATA), distro)
    token = pub_session.liveliness().declare_token(token_key)
    gid = entity_gid(token_key, distro)

    publisher = pub_session.declare_publisher(key)
    wrong = pub_session.declare_publisher(
        topic_key(0, "/robot/ps0", RANGE, "RIHS01_" + "0" * 64, distro)
    )
    assert wait_until(lambda: bool(publisher.matching_status), timeout_s=10)
    # Samples without an attachment are dropped; sent until one is, they also prove the
    # route works (the first put after matching can still be lost while the route forms).
    assert wait_until(lambda: publisher.put(b"\x00\x01\x00\x00") or subscription.dropped > 0, 10)
    wrong.put(encode_message(_range_message(distro, 9.0), distro),
              attachment=encode_attachment(Attachment(99, 0, gid), distro))  # fmt: skip
    sent_at = time.time_ns()
    for seq, value in enumerate((0.125, 0.0625, 0.03125), start=1):
        publisher.put(
            encode_message(_range_message(distro, value), distro),
            attachment=encode_attachment(Attachment(seq, sent_at + seq, gid), distro),
        )
    assert wait_until(lambda: len(subscription.received) == 3, 10), subscription.received
    with subscription.lock:
        assert [(s, t - sent_at, g, r) for s, t, g, r in subscription.received] == [
            (1, 1, gid, 0.125), (2, 2, gid, 0.0625), (3, 3, gid, 0.03125)
        ]  # fmt: skip

    replies = list(sub_session.liveliness().get(graph_key(0), timeout=5))
    tokens = [parse_token(str(r.ok.key_expr), distro) for r in replies if r.ok is not None]
    assert [(t.kind, t.node.name, t.node.namespace, t.topic and t.topic.topic) for t in tokens] == [
        (EntityKind.PUBLISHER, "epuck", "/robot", "/robot/ps0")
    ]
    assert tokens[0].topic is not None and tokens[0].topic.type_hash == hash_
    for entity in (token, publisher, wrong, subscription.sub):
        entity.undeclare()
