"""ROS 2 messages: CDR payloads and RIHS01 type hashes, from the ``rosbags`` package.

The definitions come from rosbags' built-in store of each distribution
(``Stores.ROS2_HUMBLE``, ``ROS2_JAZZY``, ``ROS2_KILTED``; :mod:`ego.ros2.distros` names
it), never from a table typed here: rosbags serializes CDR and computes REP-2011's
RIHS01 hash (``Typestore.hash_rihs01``). The definitions do differ: Humble's
sensor_msgs/Range has no ``variance`` field, so its payload is 4 bytes shorter.

rmw_zenoh's payload is the message in plain CDR (XCDR1, ``DDS_CDR``) after the 4-byte
encapsulation header (``ser.serialize_encapsulation()``, jazzy
``src/detail/type_support.cpp:97-98``; ``src/detail/cdr.cpp:25-27``), in the host's byte
order: ``00 01 00 00`` then little-endian data on x86 and ARM. Humble's key carries
``TypeHashNotSupported`` instead of a hash (:func:`type_hash` returns it).

rosbags is imported on first use: ``import ego`` never imports it, and a missing
rosbags is one :class:`~ego.errors.EgoError` line naming the pip command.

Usage::

    Range = message_class("sensor_msgs/msg/Range", "jazzy")
    payload = encode_message(msg, "jazzy")                 # b'\\x00\\x01\\x00\\x00...'
    decode_message(payload, "sensor_msgs/msg/Range", "jazzy").range
"""

from __future__ import annotations

import struct
from functools import cache
from typing import TYPE_CHECKING, Any

from ego.errors import FrameError, OutOfRangeError, UnknownDeviceError
from ego.ros2.distros import Distro, distro_format
from ego.ros2.extras import missing

if TYPE_CHECKING:
    from rosbags.typesys.store import Typestore

__all__ = [
    "EPUCK_TYPES",
    "decode_message",
    "encode_message",
    "message_class",
    "type_hash",
    "typestore",
]

#: The types cyberbotics/epuck_ros2@91ff8a1fcc31db716e0add0a02e830dd910de669 publishes
#: and subscribes (epuck_ros2_driver/src/driver.cpp:140-168, epuck_ros2_camera/src/
#: camera.cpp:73-77), plus sensor_msgs/JointState for wheel joints.
EPUCK_TYPES = (
    "geometry_msgs/msg/Twist",  # driver.cpp:140 cmd_vel
    "std_msgs/msg/Int32",  # driver.cpp:143-145 /led1 /led3 /led5 /led7 (RGB)
    "std_msgs/msg/Bool",  # driver.cpp:147-150 /led0 /led2 /led4 /led6
    "sensor_msgs/msg/LaserScan",  # driver.cpp:152 scan
    "sensor_msgs/msg/Range",  # driver.cpp:154,157,160 /gs0.., ps0.., tof
    "nav_msgs/msg/Odometry",  # driver.cpp:155 odom
    "sensor_msgs/msg/Illuminance",  # driver.cpp:158 ls0..
    "sensor_msgs/msg/Imu",  # driver.cpp:161 imu
    "tf2_msgs/msg/TFMessage",  # driver.cpp:165,168 tf2_ros broadcasters: /tf, /tf_static
    "sensor_msgs/msg/CompressedImage",  # camera.cpp:73 image_raw/compressed
    "sensor_msgs/msg/Image",  # camera.cpp:74 image_raw
    "sensor_msgs/msg/CameraInfo",  # camera.cpp:77 camera_info
    "sensor_msgs/msg/JointState",  # not in epuck_ros2; webots_ros2's e-puck publishes it
)

#: The encapsulation headers of plain CDR: big-endian and little-endian (XCDR1).
_ENCAPSULATIONS = (b"\x00\x00", b"\x00\x01")


def typestore(distro: Distro | str) -> Typestore:
    """rosbags' store of ``distro``'s message definitions (made once per distribution)."""
    distro_format(distro)  # an unknown name says so before rosbags is looked for
    return _typestore(Distro(distro))


@cache
def _typestore(distro: Distro) -> Typestore:
    try:
        from rosbags.typesys import Stores, get_typestore
    except ModuleNotFoundError as exc:
        raise missing(exc, "rosbags", "rosbags") from exc
    return get_typestore(Stores[distro_format(distro).typestore])


def _store(distro: Distro | str, type_name: str) -> Typestore:
    store = typestore(distro)
    if not isinstance(type_name, str) or type_name not in store.types:
        raise UnknownDeviceError(
            f"message type {str(type_name)[:120]!r} is not in rosbags' "
            f"{Distro(distro).value} store (names look like 'sensor_msgs/msg/Range')"
        )
    return store


def message_class(type_name: str, distro: Distro | str) -> Any:
    """The dataclass rosbags made for ``type_name`` (``pkg/msg/Name``) in ``distro``."""
    return _store(distro, type_name).types[type_name]


def type_hash(type_name: str, distro: Distro | str) -> str:
    """What ``distro``'s rmw_zenoh writes as ``type_name``'s hash: ``RIHS01_<64 hex>``
    (REP-2011), or Humble's ``TypeHashNotSupported``."""
    store = _store(distro, type_name)
    fixed = distro_format(distro).fixed_type_hash
    return fixed if fixed is not None else store.hash_rihs01(type_name)


def encode_message(message: Any, distro: Distro | str) -> bytes:
    """``message`` (a :func:`message_class` instance) as rmw_zenoh's payload: the
    little-endian CDR encapsulation header, then the CDR data. A number too big for its
    field is an :class:`~ego.errors.OutOfRangeError`."""
    type_name = getattr(message, "__msgtype__", None)
    if type_name is None:
        raise TypeError(f"{type(message).__name__} is not a ROS 2 message of ego.ros2")
    store = _store(distro, type_name)
    try:
        return bytes(store.serialize_cdr(message, type_name, little_endian=True))
    except (struct.error, OverflowError) as exc:  # a number too big for its field
        raise OutOfRangeError(f"{type_name} message cannot be serialized: {exc}") from exc
    except (AttributeError, TypeError, ValueError, IndexError) as exc:
        raise FrameError(f"{type_name} message cannot be serialized: {exc}") from exc


def decode_message(
    payload: bytes | bytearray | memoryview, type_name: str, distro: Distro | str
) -> Any:
    """The ``type_name`` message in ``payload`` (encapsulation header first);
    :class:`~ego.errors.FrameError` if the payload is not one."""
    store = _store(distro, type_name)
    raw = bytes(payload)
    if len(raw) < 4 or raw[:2] not in _ENCAPSULATIONS:
        raise FrameError(
            f"{type_name} payload starts {raw[:4].hex() or 'empty'}, not a plain CDR "
            "encapsulation header (0000 or 0001)"
        )
    try:
        return store.deserialize_cdr(raw, type_name)
    except Exception as exc:  # rosbags raises whatever struct/numpy/codecs raise
        raise FrameError(f"{type_name} payload of {len(raw)} bytes is malformed: {exc}") from exc
