"""Liveliness tokens: how a node, a publisher or a subscription shows in ROS 2's graph.

rmw_zenoh declares one Zenoh liveliness token per entity; ``ros2 node list`` and
``ros2 topic list`` read them (the graph cache subscribes to ``@ros2_lv/<domain>/**``,
jazzy ``src/detail/liveliness_utils.cpp:428-432``). The key (:449-478, ``Entity::Entity``)::

    @ros2_lv/<domain>/<zid>/<node id>/<entity id>/<NN|MP|MS|SS|SC>/<enclave>/<namespace>/<node>
        [/<topic>/<DDS type name>/<type hash>/<QoS>]

Every name field goes through ``mangle_name`` (:697-708): each ``/`` becomes ``%``, so
the root namespace and the default enclave ``/`` are ``%`` and ``/robot/ps0`` is
``%robot%ps0``. ``<zid>`` is the Zenoh session id as text; a node's token carries its node
id twice (``src/detail/rmw_node_data.cpp:43-54``); a publisher's or subscription's
carries its node's id, then its own id from the context-wide counter
(``src/detail/rmw_publisher_data.cpp:93-105``). The type is the DDS-mangled name
(``message_type_support->get_name()``, :102). The QoS field is :mod:`ego.ros2.qos`'s.
Humble writes the same fields (humble ``src/detail/liveliness_utils.cpp:382-431``) with
``TypeHashNotSupported`` as hash.

Usage::

    node = NodeInfo(domain_id=0, zid="1f2e3d", node_id=0, name="epuck")
    node_token(node, "jazzy")     # '@ros2_lv/0/1f2e3d/0/0/NN/%/%/epuck'
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from enum import Enum

from ego.errors import FrameError, OutOfRangeError
from ego.ros2.distros import Distro
from ego.ros2.keys import check_domain_id, check_type_hash
from ego.ros2.names import (
    check_namespace,
    check_node_name,
    check_topic,
    dds_type_name,
    ros_type_name,
)
from ego.ros2.qos import QoS, keyexpr_to_qos, qos_to_keyexpr

__all__ = [
    "ADMIN_SPACE",
    "EntityKind",
    "NodeInfo",
    "Token",
    "TopicInfo",
    "demangle_name",
    "encode_token",
    "graph_key",
    "mangle_name",
    "node_token",
    "parse_token",
    "publisher_token",
    "subscription_token",
]

#: The admin space every token lives under (liveliness_utils.cpp:122).
ADMIN_SPACE = "@ros2_lv"
_ZID = re.compile(r"[0-9a-f]{1,32}")
_ID = re.compile(r"0|[1-9][0-9]{0,19}")
#: Longer tokens are refused before they are split.
MAX_TOKEN_CHARS = 4096


class EntityKind(str, Enum):
    """The entity a token stands for (liveliness_utils.cpp:123-127)."""

    NODE = "NN"
    PUBLISHER = "MP"
    SUBSCRIPTION = "MS"
    SERVICE = "SS"
    CLIENT = "SC"


@dataclass(frozen=True, slots=True)
class NodeInfo:
    """A node as the graph knows it: domain, Zenoh session id (hex text), node id (the
    context's counter value when the node was made), namespace, name and enclave."""

    domain_id: int
    zid: str
    node_id: int
    name: str
    namespace: str = "/"
    enclave: str = "/"


@dataclass(frozen=True, slots=True)
class TopicInfo:
    """What a publisher's or subscription's token adds: fully qualified topic,
    ``pkg/msg/Name``, type hash and QoS."""

    topic: str
    type_name: str
    type_hash: str
    qos: QoS


@dataclass(frozen=True, slots=True)
class Token:
    """A parsed token: its kind, node, entity id and (but for nodes) topic."""

    kind: EntityKind
    node: NodeInfo
    entity_id: int
    topic: TopicInfo | None = None


def mangle_name(name: str) -> str:
    """``name`` with every ``/`` as ``%`` (rmw_zenoh's ``mangle_name``)."""
    return name.replace("/", "%")


def demangle_name(field: str) -> str:
    """The reverse of :func:`mangle_name`."""
    return field.replace("%", "/")


def graph_key(domain_id: int) -> str:
    """The key expression the graph cache subscribes to: every token of the domain."""
    return f"{ADMIN_SPACE}/{check_domain_id(domain_id)}/**"


def _check_node(node: NodeInfo) -> None:
    check_domain_id(node.domain_id)
    if not isinstance(node.zid, str) or not _ZID.fullmatch(node.zid):
        raise FrameError(f"Zenoh id {str(node.zid)[:40]!r} is not 1..32 lowercase hex digits")
    _check_id(node.node_id, "node id")
    check_namespace(node.namespace)
    check_node_name(node.name)
    check_namespace(node.enclave)


def _check_id(value: int, what: str) -> None:
    if isinstance(value, bool) or not isinstance(value, int):
        raise TypeError(f"{what} must be an int, not {type(value).__name__}")
    if not 0 <= value < 2**64:
        raise OutOfRangeError(f"{what} {value} is outside 0..{2**64 - 1}")


def encode_token(token: Token, distro: Distro | str) -> str:
    """The liveliness key expression of ``token`` as ``distro``'s rmw_zenoh writes it."""
    node = token.node
    _check_node(node)
    _check_id(token.entity_id, "entity id")
    kind = EntityKind(token.kind)
    if (kind is EntityKind.NODE) != (token.topic is None):
        verb = "has no" if token.topic is not None else "needs a"
        raise FrameError(f"a {kind.name.lower()} token {verb} topic")
    parts = [ADMIN_SPACE, str(node.domain_id), node.zid, str(node.node_id),
             str(token.entity_id), kind.value, mangle_name(node.enclave),
             mangle_name(node.namespace), node.name]  # fmt: skip
    if token.topic is not None:
        info = token.topic
        parts += [
            mangle_name(check_topic(info.topic)),
            mangle_name(dds_type_name(info.type_name)),
            mangle_name(check_type_hash(info.type_hash, distro)),
            qos_to_keyexpr(info.qos, distro),
        ]
    return "/".join(parts)


def node_token(node: NodeInfo, distro: Distro | str) -> str:
    """The token of ``node`` itself (``ros2 node list``); its entity id is its node id."""
    return encode_token(Token(EntityKind.NODE, node, node.node_id), distro)


def publisher_token(node: NodeInfo, entity_id: int, topic: TopicInfo, distro: Distro | str) -> str:
    """The token of a publisher of ``topic`` (``ros2 topic list``, ``ros2 topic info``)."""
    return encode_token(Token(EntityKind.PUBLISHER, node, entity_id, topic), distro)


def subscription_token(
    node: NodeInfo, entity_id: int, topic: TopicInfo, distro: Distro | str
) -> str:
    """The token of a subscription to ``topic``."""
    return encode_token(Token(EntityKind.SUBSCRIPTION, node, entity_id, topic), distro)


def parse_token(key: str, distro: Distro | str) -> Token:
    """The :class:`Token` a liveliness key expression stands for (``Entity::make``,
    liveliness_utils.cpp:536-621); :class:`~ego.errors.FrameError` if it is not one."""
    if len(key) > MAX_TOKEN_CHARS:
        raise FrameError(f"liveliness token of {len(key)} characters (at most {MAX_TOKEN_CHARS})")
    parts = key.split("/")
    if len(parts) not in (9, 13) or parts[0] != ADMIN_SPACE or "" in parts:
        raise FrameError(
            f"liveliness token {key[:200]!r} is not '{ADMIN_SPACE}/domain/zid/nid/id/KIND/"
            "enclave/namespace/node[/topic/type/hash/qos]'"
        )
    try:
        kind = EntityKind(parts[5])
    except ValueError:
        kinds = ", ".join(k.value for k in EntityKind)
        raise FrameError(f"liveliness token kind {parts[5][:10]!r} is not one of {kinds}") from None
    for field, what in ((parts[1], "domain"), (parts[3], "node id"), (parts[4], "entity id")):
        if not _ID.fullmatch(field):
            raise FrameError(f"liveliness token {what} {field[:30]!r} is not a number")
    node = NodeInfo(int(parts[1]), parts[2], int(parts[3]), demangle_name(parts[8]),
                    demangle_name(parts[7]), demangle_name(parts[6]))  # fmt: skip
    try:
        _check_node(node)
        _check_id(int(parts[4]), "entity id")
    except OutOfRangeError as exc:
        raise FrameError(f"liveliness token {key[:200]!r}: {exc}") from exc

    topic = None
    if len(parts) == 13:
        topic = TopicInfo(
            check_topic(demangle_name(parts[9])),
            ros_type_name(demangle_name(parts[10])),
            check_type_hash(demangle_name(parts[11]), distro),
            keyexpr_to_qos(parts[12], distro),
        )
    token = Token(kind, node, int(parts[4]), topic)
    if (kind is EntityKind.NODE) != (topic is None):
        raise FrameError(f"liveliness token {key[:200]!r}: {kind.value} with the wrong fields")
    return token
