"""ROS 2 without ROS: the formats of rmw_zenoh, ROS 2's Zenoh middleware, with no I/O.

Each module turns values into the bytes or strings rmw_zenoh puts on the wire and back,
for each distribution in :mod:`ego.ros2.distros` (Humble, Jazzy, Kilted):

- :mod:`ego.ros2.keys`: a topic's data key expression;
- :mod:`ego.ros2.attachment`: the 33-byte attachment every sample carries;
- :mod:`ego.ros2.liveliness` and :mod:`ego.ros2.qos`: the liveliness tokens that make
  nodes and topics show in ``ros2 node list`` and ``ros2 topic list``;
- :mod:`ego.ros2.messages`: CDR payloads and RIHS01 type hashes (needs ``rosbags``);
- :mod:`ego.ros2.gid`: the GID rmw_zenoh derives from a token (needs ``xxhash``).

Both optional packages come with ``pip install 'ego[ros2]'``; this package imports
neither until they are used. The I/O side lives in two modules of its own, imported only
when asked for: :mod:`ego.ros2.participant` (a node, its publishers and subscriptions
and their tokens on a Zenoh session) and :mod:`ego.ros2.topic` (a topic read and written
by a controller); ``ego ros2`` (:mod:`ego.servers.ros2_node`) bridges a whole robot.
FORMATS.md, beside this file, lists every format detail
with the rmw_zenoh source line it follows.
"""

from __future__ import annotations

from ego.ros2.attachment import Attachment, attachment_size, decode_attachment, encode_attachment
from ego.ros2.distros import FORMATS, Distro, DistroFormat, distro_format
from ego.ros2.keys import TopicKey, parse_topic_key, topic_key
from ego.ros2.liveliness import (
    EntityKind,
    NodeInfo,
    Token,
    TopicInfo,
    graph_key,
    node_token,
    parse_token,
    publisher_token,
    subscription_token,
)
from ego.ros2.names import dds_type_name, resolve_topic, ros_type_name
from ego.ros2.qos import DEFAULT_QOS, SENSOR_DATA, QoS, keyexpr_to_qos, qos_to_keyexpr

__all__ = [
    "DEFAULT_QOS",
    "FORMATS",
    "SENSOR_DATA",
    "Attachment",
    "Distro",
    "DistroFormat",
    "EntityKind",
    "NodeInfo",
    "QoS",
    "Token",
    "TopicInfo",
    "TopicKey",
    "attachment_size",
    "dds_type_name",
    "decode_attachment",
    "distro_format",
    "encode_attachment",
    "graph_key",
    "keyexpr_to_qos",
    "node_token",
    "parse_token",
    "parse_topic_key",
    "publisher_token",
    "qos_to_keyexpr",
    "resolve_topic",
    "ros_type_name",
    "subscription_token",
    "topic_key",
]
