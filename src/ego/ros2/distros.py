"""What differs between the ROS 2 distributions' rmw_zenoh formats, as one table.

Every format module looks its distribution up here; none branches on a distribution's
name. The sources are rmw_zenoh_cpp as released for each distribution, read from the
release repository ``ros2-gbp/rmw_zenoh-release`` (one tag per release; the files sit at
its root, so ``src/detail/...`` below is ``rmw_zenoh_cpp/src/detail/...`` upstream):

========  =========================  ==========================================
distro    release tag                commit
========  =========================  ==========================================
humble    rmw_zenoh_cpp 0.1.9-1      79eeaa2d2bdeac4e8741d9ecf0da2079c2777415
jazzy     rmw_zenoh_cpp 0.2.10-1     d38ea19c0312ace03d8e0c26990ea52fdcd315e1
kilted    rmw_zenoh_cpp 0.6.7-1      70c38f56ca02ce69042a302efd618e5c0fa9b251
========  =========================  ==========================================

Rolling (0.12.0-1, 3c15909469ed2ee4b5eee09567840ff1e8236f17) is left out on purpose:
its publishers of types with rosidl buffer fields also publish on ``<key>/_buf_cpu``
(``src/detail/buffer_endpoint_helpers.hpp:62-65``) and its tokens may carry a 14th
``backends:`` field (``src/detail/liveliness_utils.cpp:176-187``); FORMATS.md says more.

Usage::

    from ego.ros2.distros import Distro, distro_format
    fmt = distro_format("jazzy")
    fmt.gid_size   # 16
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from enum import Enum
from types import MappingProxyType

from ego.errors import UnknownDeviceError

__all__ = ["FORMATS", "Distro", "DistroFormat", "distro_format"]


class Distro(str, Enum):
    """A ROS 2 distribution whose rmw_zenoh format ego speaks."""

    HUMBLE = "humble"
    JAZZY = "jazzy"
    KILTED = "kilted"


@dataclass(frozen=True, slots=True)
class DistroFormat:
    """One distribution's rmw_zenoh format details.

    ``fixed_type_hash`` is the constant written where the type hash goes, or None where
    the hash is the type's RIHS01 string. ``gid_size`` is the number of GID bytes in the
    attachment and the GID rmw_zenoh derives from a liveliness key. ``typestore`` names
    the rosbags store (``rosbags.typesys.Stores`` member) holding the distribution's
    message definitions. ``reliability``, ``durability``, ``history`` and ``liveliness``
    are the rmw enum values a liveliness token's QoS field may carry (rmw/types.h).
    ``release`` and ``commit`` say which rmw_zenoh_cpp source this row follows.
    """

    release: str
    commit: str
    fixed_type_hash: str | None
    gid_size: int
    typestore: str
    reliability: frozenset[int]
    durability: frozenset[int]
    history: frozenset[int]
    liveliness: frozenset[int]


# rmw/types.h enum values: SYSTEM_DEFAULT 0, RELIABLE/TRANSIENT_LOCAL/KEEP_LAST/AUTOMATIC 1,
# BEST_EFFORT/VOLATILE/KEEP_ALL 2, UNKNOWN 3 (liveliness: MANUAL_BY_TOPIC 3, UNKNOWN 4).
# BEST_AVAILABLE (4 for reliability and durability, 5 for liveliness) arrived after
# Humble: ros2/rmw@e5901447 (humble) rmw/include/rmw/types.h:373-456 has none,
# ros2/rmw@c90c2970 (jazzy) rmw/include/rmw/types.h:370-513 has them; rmw_zenoh's maps
# follow (jazzy src/detail/liveliness_utils.cpp:156-188, humble :156-181).
_HUMBLE_RELIABILITY = frozenset({0, 1, 2, 3})
_IRON_ON_RELIABILITY = frozenset({0, 1, 2, 3, 4})
_HISTORY = frozenset({0, 1, 2, 3})
_HUMBLE_LIVELINESS = frozenset({0, 1, 3, 4})
_IRON_ON_LIVELINESS = frozenset({0, 1, 3, 4, 5})

_TABLE: dict[Distro, DistroFormat] = {
    # humble src/detail/rmw_publisher_data.cpp:73-75: "Humble doesn't support type hash",
    # the constant "TypeHashNotSupported"; src/detail/attachment_helpers.cpp:35,81: the
    # GID is std::array<uint8_t, 16> (Humble's RMW_GID_STORAGE_SIZE is 24, unused here).
    Distro.HUMBLE: DistroFormat(
        release="rmw_zenoh_cpp 0.1.9-1",
        commit="79eeaa2d2bdeac4e8741d9ecf0da2079c2777415",
        fixed_type_hash="TypeHashNotSupported",
        gid_size=16,
        typestore="ROS2_HUMBLE",
        reliability=_HUMBLE_RELIABILITY,
        durability=_HUMBLE_RELIABILITY,
        history=_HISTORY,
        liveliness=_HUMBLE_LIVELINESS,
    ),
    # jazzy src/detail/rmw_publisher_data.cpp:76-90: rosidl_stringify_type_hash, i.e.
    # "RIHS01_<64 hex>"; src/detail/attachment_helpers.cpp:35,81: RMW_GID_STORAGE_SIZE,
    # 16 since Iron (ros2/rmw@c90c2970 rmw/include/rmw/types.h:40-44).
    Distro.JAZZY: DistroFormat(
        release="rmw_zenoh_cpp 0.2.10-1",
        commit="d38ea19c0312ace03d8e0c26990ea52fdcd315e1",
        fixed_type_hash=None,
        gid_size=16,
        typestore="ROS2_JAZZY",
        reliability=_IRON_ON_RELIABILITY,
        durability=_IRON_ON_RELIABILITY,
        history=_HISTORY,
        liveliness=_IRON_ON_LIVELINESS,
    ),
    # kilted: liveliness_utils.cpp and attachment_helpers.cpp are byte for byte jazzy's.
    Distro.KILTED: DistroFormat(
        release="rmw_zenoh_cpp 0.6.7-1",
        commit="70c38f56ca02ce69042a302efd618e5c0fa9b251",
        fixed_type_hash=None,
        gid_size=16,
        typestore="ROS2_KILTED",
        reliability=_IRON_ON_RELIABILITY,
        durability=_IRON_ON_RELIABILITY,
        history=_HISTORY,
        liveliness=_IRON_ON_LIVELINESS,
    ),
}

#: Each supported distribution's format, read-only.
FORMATS: Mapping[Distro, DistroFormat] = MappingProxyType(_TABLE)


def distro_format(distro: Distro | str) -> DistroFormat:
    """The format row of ``distro`` (a :class:`Distro` or its name, e.g. ``"jazzy"``).

    An unknown name raises :class:`~ego.errors.UnknownDeviceError` listing the known ones.
    """
    try:
        return FORMATS[Distro(distro)]
    except ValueError:
        known = ", ".join(d.value for d in Distro)
        raise UnknownDeviceError(
            f"ROS 2 distribution {distro!r} is not one ego speaks (known: {known})"
        ) from None
