"""Message payloads and type hashes: ego (through rosbags) against independent code.

Sources: jazzy ros2-gbp/rmw_zenoh-release@d38ea19c src/detail/type_support.cpp:97-98
(``ser.serialize_encapsulation()``) and src/detail/cdr.cpp:25-27 (``DEFAULT_ENDIAN``,
``DDS_CDR``): the payload is the CDR encapsulation header, then plain CDR in the host's
byte order. Type hashes: REP-2011, checked with ros2_support.rihs01 (hashlib, no
rosbags) and against the hashes rmw_zenoh's and ros-z's documents print.
"""

from __future__ import annotations

from typing import Any

import pytest
from helpers import SUBNORMALS
from hypothesis import given
from hypothesis import strategies as st
from ros2_support import CdrReader, CdrWriter, describe, field_entry, rihs01

from ego.errors import FrameError, OutOfRangeError, UnknownDeviceError
from ego.ros2.messages import (
    EPUCK_TYPES,
    decode_message,
    encode_message,
    message_class,
    type_hash,
    typestore,
)

#: The .msg texts of ros2/common_interfaces and rcl_interfaces (Jazzy), constants included.
MSG_TEXT = {
    "std_msgs/msg/String": "string data",
    "std_msgs/msg/Bool": "bool data",
    "std_msgs/msg/Int32": "int32 data",
    "builtin_interfaces/msg/Time": "int32 sec\nuint32 nanosec",
    "std_msgs/msg/Header": "builtin_interfaces/Time stamp\nstring frame_id",
    "geometry_msgs/msg/Vector3": "float64 x\nfloat64 y\nfloat64 z",
    "geometry_msgs/msg/Twist": "Vector3 linear\nVector3 angular",
    "sensor_msgs/msg/Range": (
        "std_msgs/Header header\nuint8 ULTRASOUND=0\nuint8 INFRARED=1\nuint8 radiation_type\n"
        "float32 field_of_view\nfloat32 min_range\nfloat32 max_range\nfloat32 range\n"
        "float32 variance"
    ),
    "sensor_msgs/msg/Illuminance": "std_msgs/Header header\nfloat64 illuminance\nfloat64 variance",
}


@pytest.mark.parametrize("distro", ["jazzy", "kilted"])
@pytest.mark.parametrize("type_name", sorted(MSG_TEXT))
def test_hashes_equal_rep_2011_computed_from_the_msg_text(distro: str, type_name: str) -> None:
    assert type_hash(type_name, distro) == rihs01(type_name, lambda n: describe(n, MSG_TEXT[n]))


def test_hashes_equal_the_ones_rmw_zenoh_and_ros_z_print() -> None:
    # ros2/rmw_zenoh@99a6a2bd docs/design.md: the chatter key ends in this hash.
    assert type_hash("std_msgs/msg/String", "jazzy") == (
        "RIHS01_df668c740482bbd48fb39d76a70dfd4bd59db1288021743503259e948f6b1a18"
    )
    # ZettaScaleLabs/ros-z docs/bindings/python-codegen.md:74 (geometry_msgs/Twist).
    assert type_hash("geometry_msgs/msg/Twist", "kilted") == (
        "RIHS01_9c45bf16fe0983d80e3cfe750d6835843d265a9a6c46bd2e609fcddde6fb8d2a"
    )


def _rosbags_description(store: Any, type_name: str) -> dict[str, Any]:
    """A type description from rosbags' parsed fields, built by this test's own code."""
    names = {1: "BASE", 2: "NAME", 3: "ARRAY", 4: "SEQUENCE"}

    def text(desc: Any) -> str:
        kind, rest = names[int(desc[0])], desc[1]
        if kind == "NAME":
            return str(rest)
        if kind == "BASE":
            base, bound = rest
            return f"{base}<={bound}" if bound else str(base)
        inner, count = rest
        if kind == "ARRAY":
            return f"{text(inner)}[{count}]"
        return f"{text(inner)}[<={count}]" if count else f"{text(inner)}[]"

    fields = [field_entry(text(desc), name, "") for name, desc in store.fielddefs[type_name][1]]
    fields = fields or [field_entry("uint8", "structure_needs_at_least_one_member", "")]
    return {"type_name": type_name, "fields": fields}


@pytest.mark.parametrize("distro", ["jazzy", "kilted"])
@pytest.mark.parametrize("type_name", EPUCK_TYPES)
def test_every_epuck_type_hash_is_rep_2011_of_its_definition(distro: str, type_name: str) -> None:
    store = typestore(distro)
    expected = rihs01(type_name, lambda n: _rosbags_description(store, n))
    assert type_hash(type_name, distro) == expected


@pytest.mark.parametrize("type_name", EPUCK_TYPES)
def test_humble_has_no_type_hashes(type_name: str) -> None:
    assert type_hash(type_name, "humble") == "TypeHashNotSupported"


def _range(distro: str, **extra: float) -> Any:
    time = message_class("builtin_interfaces/msg/Time", distro)(sec=1, nanosec=2)
    header = message_class("std_msgs/msg/Header", distro)(stamp=time, frame_id="ps0")
    return message_class("sensor_msgs/msg/Range", distro)(
        header=header, radiation_type=1, field_of_view=0.5, min_range=0.0,
        max_range=0.25, range=0.125, **extra,
    )  # fmt: skip


def test_a_jazzy_range_is_pinned_and_reads_back_with_an_independent_reader() -> None:
    payload = encode_message(_range("jazzy", variance=0.0), "jazzy")
    # 00 01 00 00 encapsulation; sec, nanosec; "ps0\0" (length 4); radiation_type; 3 pad
    # bytes (float32 aligns to 4 after the header); five float32.
    assert payload.hex() == (
        "00010000" "01000000" "02000000" "04000000" "70733000" "01000000"
        "0000003f" "00000000" "0000803e" "0000003e" "00000000"
    )  # fmt: skip
    r = CdrReader(payload)
    assert (r.read("int32"), r.read("uint32"), r.string()) == (1, 2, "ps0")
    assert r.read("uint8") == 1
    assert [r.read("float32") for _ in range(5)] == [0.5, 0.0, 0.25, 0.125, 0.0]
    assert r.done()


def test_humbles_range_has_no_variance_so_its_payload_is_4_bytes_shorter() -> None:
    humble = encode_message(_range("humble"), "humble")
    assert len(humble) == 40 and len(encode_message(_range("jazzy", variance=0.0), "jazzy")) == 44
    with pytest.raises(TypeError):
        _range("humble", variance=0.0)


def test_ego_reads_payloads_an_independent_writer_makes() -> None:
    twist = CdrWriter()
    for value in (0.1, 0.0, 0.0, 0.0, 0.0, -1.5):
        twist.write("float64", value)
    msg = decode_message(twist.payload(), "geometry_msgs/msg/Twist", "jazzy")
    assert (msg.linear.x, msg.angular.z) == (0.1, -1.5)
    scan = CdrWriter().write("int32", 5).write("uint32", 6).string("laser")
    for value in (-3.0, 3.0, 0.5, 0.0, 0.1, 0.005, 0.3):  # angle_min .. range_max
        scan.write("float32", value)
    scan.write("uint32", 3)
    for value in (0.25, 0.125, 0.0625):
        scan.write("float32", value)
    scan.write("uint32", 0)  # intensities
    msg = decode_message(scan.payload(), "sensor_msgs/msg/LaserScan", "kilted")
    assert msg.header.frame_id == "laser" and list(msg.ranges) == [0.25, 0.125, 0.0625]
    led = decode_message(
        CdrWriter().write("int32", 0xFF0000).payload(), "std_msgs/msg/Int32", "humble"
    )
    assert led.data == 0xFF0000


@given(
    values=st.lists(
        st.floats(allow_nan=False, width=64, allow_subnormal=SUBNORMALS), min_size=6, max_size=6
    )
)
def test_twists_round_trip_and_read_with_the_independent_reader(values: list[float]) -> None:
    vector = message_class("geometry_msgs/msg/Vector3", "jazzy")
    twist = message_class("geometry_msgs/msg/Twist", "jazzy")(
        vector(*values[:3]), vector(*values[3:])
    )
    payload = encode_message(twist, "jazzy")
    reader = CdrReader(payload)
    assert [reader.read("float64") for _ in range(6)] == values and reader.done()
    assert decode_message(payload, "geometry_msgs/msg/Twist", "jazzy") == twist


@pytest.mark.parametrize(
    ("call", "error", "message"),
    [
        (lambda: decode_message(b"\x01\x00\x00\x00", "std_msgs/msg/Int32", "jazzy"), FrameError,
         "std_msgs/msg/Int32 payload starts 01000000, not a plain CDR encapsulation header"),
        (lambda: decode_message(b"\x00\x01\x00\x00\x01", "std_msgs/msg/Int32", "jazzy"), FrameError,
         "std_msgs/msg/Int32 payload of 5 bytes is malformed"),
        (lambda: decode_message(b"", "std_msgs/msg/Int32", "jazzy"), FrameError,
         "payload starts empty"),
        (lambda: type_hash("std_msgs/msg/Nope", "jazzy"), UnknownDeviceError,
         "message type 'std_msgs/msg/Nope' is not in rosbags' jazzy store"),
        (lambda: encode_message(message_class("std_msgs/msg/Int32", "jazzy")(2**40), "jazzy"),
         OutOfRangeError, "std_msgs/msg/Int32 message cannot be serialized: 'i' format requires"),
        (lambda: encode_message(object(), "jazzy"), TypeError,
         "object is not a ROS 2 message of ego.ros2"),
    ],
)  # fmt: skip
def test_bad_payloads_and_types_are_refused_in_one_line(
    call: object, error: type[Exception], message: str
) -> None:
    with pytest.raises(error) as caught:
        call()  # type: ignore[operator]
    assert message in str(caught.value) and "\n" not in str(caught.value)
