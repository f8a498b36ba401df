"""QoS profiles as rmw_zenoh writes them in a liveliness token's last field.

``<reliability>:<durability>:<history>,<depth>:<deadline s>,<ns>:<lifespan s>,<ns>:
<liveliness>,<lease s>,<lease ns>`` with every value left empty where it equals
rmw_zenoh's default (jazzy ``src/detail/liveliness_utils.cpp:290-351``,
``qos_to_keyexpr``; read back by ``keyexpr_to_qos``, :354-426; humble :237-299 and
:301-373 write the same text). The defaults (``src/detail/qos.cpp:18-33``, the same in
the humble, jazzy and kilted releases) are KEEP_LAST, depth 42, RELIABLE, VOLATILE,
infinite deadline, lifespan and lease, AUTOMATIC liveliness. Before writing, rmw_zenoh
adapts the profile (``QoS::best_available_qos``, jazzy ``src/detail/qos.cpp:78-150``):
system-default policies and a depth of 0 become the defaults, and unspecified
durations become infinite. The numbers are rmw's enum values (rmw/types.h).

Usage::

    qos_to_keyexpr(QoS(depth=10), "jazzy")          # '::,10:,:,:,,'
    qos_to_keyexpr(SENSOR_DATA, "jazzy")            # '2::,5:,:,:,,'
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from enum import IntEnum
from typing import NamedTuple

from ego.errors import FrameError, OutOfRangeError
from ego.ros2.distros import Distro, distro_format

__all__ = [
    "DEFAULT_QOS",
    "INFINITE",
    "SENSOR_DATA",
    "UNSPECIFIED",
    "Durability",
    "Duration",
    "History",
    "Liveliness",
    "QoS",
    "Reliability",
    "adapt",
    "keyexpr_to_qos",
    "qos_to_keyexpr",
]

_UINT64_MAX = 2**64 - 1
#: Longer QoS fields are refused before they are split.
MAX_QOS_CHARS = 256


class Reliability(IntEnum):
    """rmw_qos_reliability_policy_e (BEST_AVAILABLE from Iron on)."""

    SYSTEM_DEFAULT = 0
    RELIABLE = 1
    BEST_EFFORT = 2
    UNKNOWN = 3
    BEST_AVAILABLE = 4


class Durability(IntEnum):
    """rmw_qos_durability_policy_e (BEST_AVAILABLE from Iron on)."""

    SYSTEM_DEFAULT = 0
    TRANSIENT_LOCAL = 1
    VOLATILE = 2
    UNKNOWN = 3
    BEST_AVAILABLE = 4


class History(IntEnum):
    """rmw_qos_history_policy_e."""

    SYSTEM_DEFAULT = 0
    KEEP_LAST = 1
    KEEP_ALL = 2
    UNKNOWN = 3


class Liveliness(IntEnum):
    """rmw_qos_liveliness_policy_e (2, MANUAL_BY_NODE, is deprecated and unused)."""

    SYSTEM_DEFAULT = 0
    AUTOMATIC = 1
    MANUAL_BY_TOPIC = 3
    UNKNOWN = 4
    BEST_AVAILABLE = 5


class Duration(NamedTuple):
    """An rmw_time_t: whole seconds and nanoseconds, both unsigned."""

    sec: int
    nsec: int


#: RMW_DURATION_INFINITE (rmw/time.h:54).
INFINITE = Duration(9223372036, 854775807)
#: RMW_DURATION_UNSPECIFIED, what RMW_QOS_DEADLINE_DEFAULT and its siblings are.
UNSPECIFIED = Duration(0, 0)


@dataclass(frozen=True, slots=True)
class QoS:
    """A QoS profile; the defaults are rmw_zenoh's (what an empty field stands for)."""

    reliability: int = Reliability.RELIABLE
    durability: int = Durability.VOLATILE
    history: int = History.KEEP_LAST
    depth: int = 42
    deadline: Duration = INFINITE
    lifespan: Duration = INFINITE
    liveliness: int = Liveliness.AUTOMATIC
    lease: Duration = INFINITE


#: rmw_zenoh's default profile (src/detail/qos.cpp:18-33).
DEFAULT_QOS = QoS()
#: rmw_qos_profile_sensor_data (rmw/qos_profiles.h): best effort, volatile, depth 5.
SENSOR_DATA = QoS(reliability=Reliability.BEST_EFFORT, depth=5)

_POLICIES = ("reliability", "durability", "history", "liveliness")
#: Each policy's UNKNOWN value: jazzy's rmw_zenoh refuses a profile holding one
#: (``QoS::is_supported``, src/detail/qos.cpp:64-75), and so does ego, in every distribution.
_UNKNOWN = {"reliability": 3, "durability": 3, "history": 3, "liveliness": 4}


def adapt(qos: QoS) -> QoS:
    """``qos`` as rmw_zenoh adapts it before use (``QoS::best_available_qos``); a policy
    that is UNKNOWN is refused (:class:`~ego.errors.OutOfRangeError`)."""
    changes: dict[str, object] = {}
    for name in _POLICIES:
        value = getattr(qos, name)
        if value == _UNKNOWN[name]:
            raise OutOfRangeError(f"QoS {name} UNKNOWN ({value}) cannot be offered")
        if value == 0:
            changes[name] = getattr(DEFAULT_QOS, name)
    if qos.depth == 0:
        changes["depth"] = DEFAULT_QOS.depth
    for name in ("deadline", "lifespan", "lease"):
        if tuple(getattr(qos, name)) == UNSPECIFIED:
            changes[name] = INFINITE
    return replace(qos, **changes)  # type: ignore[arg-type]


def _check(qos: QoS, distro: Distro | str) -> None:
    fmt = distro_format(distro)
    for name in _POLICIES:
        value = getattr(qos, name)
        if isinstance(value, bool) or not isinstance(value, int):
            raise TypeError(f"QoS {name} must be an int, not {type(value).__name__}")
        if value not in getattr(fmt, name):
            allowed = ", ".join(map(str, sorted(getattr(fmt, name))))
            raise OutOfRangeError(
                f"QoS {name} {value} is not one {Distro(distro).value} knows ({allowed})"
            )
    numbers = [("depth", qos.depth)]
    numbers += [(f"{n} {part}", v) for n in ("deadline", "lifespan", "lease")
                for part, v in zip(("sec", "nsec"), getattr(qos, n), strict=True)]  # fmt: skip
    for name, value in numbers:
        if isinstance(value, bool) or not isinstance(value, int):
            raise TypeError(f"QoS {name} must be an int, not {type(value).__name__}")
        if not 0 <= value <= _UINT64_MAX:
            raise OutOfRangeError(f"QoS {name} {value} is outside 0..{_UINT64_MAX}")


def _field(value: int, default: int) -> str:
    return "" if value == default else str(int(value))


def qos_to_keyexpr(qos: QoS, distro: Distro | str) -> str:
    """The QoS field of a liveliness token for ``qos`` (adapted first, as rmw_zenoh does)."""
    qos = adapt(qos)
    _check(qos, distro)
    d = DEFAULT_QOS

    def pair(value: Duration, default: Duration) -> str:
        return f"{_field(value.sec, default.sec)},{_field(value.nsec, default.nsec)}"

    return (
        f"{_field(qos.reliability, d.reliability)}:{_field(qos.durability, d.durability)}:"
        f"{_field(qos.history, d.history)},{_field(qos.depth, d.depth)}:"
        f"{pair(Duration(*qos.deadline), d.deadline)}:{pair(Duration(*qos.lifespan), d.lifespan)}:"
        f"{_field(qos.liveliness, d.liveliness)},{pair(Duration(*qos.lease), d.lease)}"
    )


def _number(text: str, default: int, what: str, field: str) -> int:
    if text == "":
        return default
    if not (text.isascii() and text.isdigit()):
        raise FrameError(f"QoS field {field!r}: {what} {text[:30]!r} is not a number")
    return int(text)


def keyexpr_to_qos(field: str, distro: Distro | str) -> QoS:
    """The :class:`QoS` a liveliness token's QoS ``field`` stands for."""
    if len(field) > MAX_QOS_CHARS:
        raise FrameError(f"QoS field of {len(field)} characters (at most {MAX_QOS_CHARS})")
    parts = field.split(":")
    shape = [len(p.split(",")) for p in parts]
    if shape[:1] != [1] or shape[1:] != [1, 2, 2, 2, 3]:
        raise FrameError(
            f"QoS field {field!r} is not 'rel:dur:hist,depth:s,ns:s,ns:liveliness,s,ns'"
        )
    rel, dur, (hist, depth), deadline, lifespan, (liv, *lease) = (
        parts[0], parts[1], *(p.split(",") for p in parts[2:])
    )  # fmt: skip
    d = DEFAULT_QOS

    def duration(texts: list[str], default: Duration, what: str) -> Duration:
        return Duration(
            _number(texts[0], default.sec, f"{what} seconds", field),
            _number(texts[1], default.nsec, f"{what} nanoseconds", field),
        )

    qos = QoS(
        reliability=_number(rel, d.reliability, "reliability", field),
        durability=_number(dur, d.durability, "durability", field),
        history=_number(hist, d.history, "history", field),
        depth=_number(depth, d.depth, "depth", field),
        deadline=duration(deadline, d.deadline, "deadline"),
        lifespan=duration(lifespan, d.lifespan, "lifespan"),
        liveliness=_number(liv, d.liveliness, "liveliness", field),
        lease=duration(lease, d.lease, "lease"),
    )
    try:
        _check(qos, distro)
    except OutOfRangeError as exc:
        raise FrameError(f"QoS field {field!r}: {exc}") from exc
    return replace(
        qos,
        reliability=Reliability(qos.reliability),
        durability=Durability(qos.durability),
        history=History(qos.history),
        liveliness=Liveliness(qos.liveliness),
    )
