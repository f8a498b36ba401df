"""The Zenoh key expression rmw_zenoh publishes and subscribes a topic's data on.

``<domain id>/<topic name without its leading and trailing '/'>/<DDS type name>/<type hash>``:
jazzy ``src/detail/liveliness_utils.cpp:86-93`` (``TopicInfo::TopicInfo``) builds it with
``strip_slashes`` (:61-72), so slashes inside the name stay: ``/robot/ps0`` is
``0/robot/ps0/...``. The type hash is ``RIHS01_<64 hex>`` from Jazzy on
(``src/detail/rmw_publisher_data.cpp:76-90``, ``rosidl_stringify_type_hash``) and the
constant ``TypeHashNotSupported`` on Humble (humble ``src/detail/rmw_publisher_data.cpp:73-75``).
A subscription declares this exact key (jazzy ``src/detail/rmw_subscription_data.cpp:168``),
so a wrong type name or hash means no data, silently.

Usage::

    key = topic_key(0, "/robot/ps0", "sensor_msgs/msg/Range", type_hash, "jazzy")
    parse_topic_key(key, "jazzy").topic    # '/robot/ps0'
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from ego.errors import FrameError, OutOfRangeError
from ego.ros2.distros import Distro, distro_format
from ego.ros2.names import check_topic, dds_type_name, ros_type_name

__all__ = ["MAX_DOMAIN_ID", "TopicKey", "check_type_hash", "parse_topic_key", "topic_key"]

#: rmw_zenoh takes any size_t; ego keeps domain ids to 32 bits.
MAX_DOMAIN_ID = 2**32 - 1
_RIHS01 = re.compile(r"RIHS01_[0-9a-f]{64}")
#: Longer keys are refused before they are split.
MAX_KEY_CHARS = 4096


@dataclass(frozen=True, slots=True)
class TopicKey:
    """A topic's data key, parsed: domain, fully qualified topic, ``pkg/msg/Name``, hash."""

    domain_id: int
    topic: str
    type_name: str
    type_hash: str

    def __str__(self) -> str:
        topic = self.topic.strip("/")
        return f"{self.domain_id}/{topic}/{dds_type_name(self.type_name)}/{self.type_hash}"


def check_domain_id(domain_id: int) -> int:
    """``domain_id`` if it is an int in 0..MAX_DOMAIN_ID."""
    if isinstance(domain_id, bool) or not isinstance(domain_id, int):
        raise TypeError(f"domain id must be an int, not {type(domain_id).__name__}")
    if not 0 <= domain_id <= MAX_DOMAIN_ID:
        raise OutOfRangeError(f"domain id {domain_id} is outside 0..{MAX_DOMAIN_ID}")
    return domain_id


def check_type_hash(type_hash: str, distro: Distro | str) -> str:
    """``type_hash`` if it is what ``distro`` writes: ``RIHS01_<64 lowercase hex>``, or
    Humble's constant."""
    fixed = distro_format(distro).fixed_type_hash
    ok = type_hash == fixed if fixed is not None else bool(_RIHS01.fullmatch(type_hash))
    if not ok:
        want = repr(fixed) if fixed is not None else "'RIHS01_' and 64 lowercase hex digits"
        raise FrameError(
            f"type hash {type_hash[:100]!r} is not what {Distro(distro).value} writes ({want})"
        )
    return type_hash


def topic_key(
    domain_id: int, topic: str, type_name: str, type_hash: str, distro: Distro | str
) -> str:
    """The data key of ``topic`` (fully qualified) carrying ``type_name`` (``pkg/msg/Name``)."""
    key = TopicKey(
        check_domain_id(domain_id),
        check_topic(topic),
        type_name,
        check_type_hash(type_hash, distro),
    )
    return str(key)


def parse_topic_key(key: str, distro: Distro | str) -> TopicKey:
    """The parts of a data key written by :func:`topic_key` (or by rmw_zenoh)."""
    if len(key) > MAX_KEY_CHARS:
        raise FrameError(f"topic key of {len(key)} characters (at most {MAX_KEY_CHARS})")
    parts = key.split("/")
    if len(parts) < 4:
        raise FrameError(f"topic key {key[:200]!r} is not 'domain/topic/type/hash'")
    domain, *topic, dds_type, type_hash = parts
    if not domain.isdigit() or not domain.isascii() or int(domain) > MAX_DOMAIN_ID:
        raise FrameError(f"topic key {key[:200]!r}: domain {domain[:20]!r} is not a domain id")
    return TopicKey(
        check_domain_id(int(domain)),
        check_topic("/" + "/".join(topic)),
        ros_type_name(dds_type),
        check_type_hash(type_hash, distro),
    )
