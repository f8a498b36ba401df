"""The GID rmw_zenoh gives an entity: 16 bytes of XXH3-128 of its liveliness key.

jazzy ``src/detail/liveliness_utils.cpp:486-496``: ``simplified_XXH3_128bits`` of the
whole liveliness key expression, then ``low64`` and ``high64`` copied into the GID in
that order, in the host's byte order (little-endian on every machine ROS 2 ships for).
That is the canonical (big-endian) XXH3-128 digest reversed. The graph cache derives
the same GID from the token it receives, so a publisher whose attachment carries this
GID is the one ``ros2 topic info -v`` lists. Any 16 bytes deliver; only this one matches.
Needs the ``xxhash`` package (the ``ros2`` extra).

Usage::

    gid = entity_gid(publisher_token(node, 1, topic, "jazzy"), "jazzy")
"""

from __future__ import annotations

from ego.ros2.distros import Distro, distro_format
from ego.ros2.extras import missing

__all__ = ["entity_gid"]


def entity_gid(liveliness_key: str, distro: Distro | str) -> bytes:
    """The GID rmw_zenoh of ``distro`` derives from ``liveliness_key``."""
    try:
        import xxhash
    except ModuleNotFoundError as exc:
        raise missing(exc, "xxhash", "xxhash") from exc
    digest = xxhash.xxh3_128_digest(liveliness_key.encode("utf-8"))
    return digest[::-1][: distro_format(distro).gid_size]
