"""ROS 2 names: checking and resolving topic names, and the DDS-mangled type names.

rmw_zenoh writes the type of a topic as the name its Fast-CDR type support gives it,
``<package>::<kind>::dds_::<Name>_`` (``src/detail/type_support_common.cpp:39-48`` of
every release in :mod:`ego.ros2.distros`), so ``sensor_msgs/msg/Range`` travels as
``sensor_msgs::msg::dds_::Range_``. Topic names follow ROS 2's rules (rcl's
``rcl_validate_topic_name``, REP-144 style): absolute after resolution, tokens of
letters, digits and ``_`` that do not start with a digit, no empty token.

Usage::

    resolve_topic("ps0", namespace="/robot")       # '/robot/ps0'
    dds_type_name("sensor_msgs/msg/Range")         # 'sensor_msgs::msg::dds_::Range_'
"""

from __future__ import annotations

import re

from ego.errors import FrameError

__all__ = [
    "check_namespace",
    "check_node_name",
    "check_topic",
    "dds_type_name",
    "node_namespace",
    "resolve_topic",
    "ros_type_name",
]

_TOKEN = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
_TYPE = re.compile(r"(?P<pkg>[a-z][a-z0-9_]*)/(?P<kind>msg|srv|action)/(?P<name>[A-Z][A-Za-z0-9]*)")
_DDS_TYPE = re.compile(
    r"(?P<pkg>[a-z][a-z0-9_]*)::(?P<kind>msg|srv|action)::dds_::(?P<name>[A-Z][A-Za-z0-9_]*)_"
)
#: Longer names are refused before any pattern runs on them.
MAX_NAME_CHARS = 1024


def _absolute(name: str, what: str) -> str:
    if not isinstance(name, str):
        raise TypeError(f"{what} must be a string, not {type(name).__name__}")
    if len(name) > MAX_NAME_CHARS:
        raise FrameError(f"{what} of {len(name)} characters (at most {MAX_NAME_CHARS})")
    if not name.startswith("/"):
        raise FrameError(f"{what} {name!r} must be absolute (start with '/')")
    return name


def check_topic(name: str) -> str:
    """``name`` if it is a fully qualified ROS 2 topic name (``/robot/ps0``); else
    :class:`~ego.errors.FrameError` saying which rule it breaks."""
    _absolute(name, "topic name")
    tokens = name[1:].split("/")
    for token in tokens:
        if not _TOKEN.fullmatch(token):
            raise FrameError(
                f"topic name {name!r}: token {token!r} is not letters, digits and '_' "
                "(not starting with a digit, not empty)"
            )
    return name


def check_namespace(namespace: str) -> str:
    """``namespace`` if it is ``/`` or an absolute name such as ``/robot``."""
    _absolute(namespace, "namespace")
    if namespace != "/":
        check_topic(namespace)
    return namespace


def node_namespace(namespace: str) -> str:
    """A node's namespace as ROS makes it: a relative one (``epuck``) under the root
    (``/epuck``) and an empty one the root, as ``rcl_node_init`` does
    (``rcl/src/rcl/node.c``); then checked as :func:`check_namespace` does (FrameError)."""
    if isinstance(namespace, str) and not namespace.startswith("/"):
        namespace = "/" + namespace
    return check_namespace(namespace)


def check_node_name(name: str) -> str:
    """``name`` if it is a valid node name (one token: letters, digits, ``_``)."""
    if not isinstance(name, str):
        raise TypeError(f"node name must be a string, not {type(name).__name__}")
    if len(name) > MAX_NAME_CHARS or not _TOKEN.fullmatch(name):
        raise FrameError(
            f"node name {name[:80]!r} is not letters, digits and '_' (not starting with a digit)"
        )
    return name


def resolve_topic(name: str, namespace: str = "/", node: str = "") -> str:
    """The fully qualified name of topic ``name`` for a node in ``namespace``.

    Absolute names stay; relative ones go under the namespace (``ps0`` in ``/robot`` is
    ``/robot/ps0``); ``~/x`` goes under the node (``/robot/epuck/x``), as rcl expands it.
    """
    check_namespace(namespace)
    if not isinstance(name, str):
        raise TypeError(f"topic name must be a string, not {type(name).__name__}")
    base = namespace.rstrip("/")
    if name == "~" or name.startswith("~/"):
        check_node_name(node)
        name = f"{base}/{node}{name[1:]}"
    elif not name.startswith("/"):
        name = f"{base}/{name}"
    return check_topic(name)


def dds_type_name(type_name: str) -> str:
    """``pkg/msg/Name`` as rmw_zenoh writes it in keys: ``pkg::msg::dds_::Name_``."""
    match = _TYPE.fullmatch(type_name) if isinstance(type_name, str) else None
    if match is None:
        raise FrameError(f"type name {str(type_name)[:120]!r} is not 'package/msg/Name'")
    return f"{match['pkg']}::{match['kind']}::dds_::{match['name']}_"


def ros_type_name(dds_name: str) -> str:
    """The reverse of :func:`dds_type_name`: ``pkg::msg::dds_::Name_`` to ``pkg/msg/Name``."""
    match = _DDS_TYPE.fullmatch(dds_name) if isinstance(dds_name, str) else None
    if match is None or not _TYPE.fullmatch(f"{match['pkg']}/{match['kind']}/{match['name']}"):
        raise FrameError(f"type {str(dds_name)[:120]!r} is not 'package::msg::dds_::Name_'")
    return f"{match['pkg']}/{match['kind']}/{match['name']}"
