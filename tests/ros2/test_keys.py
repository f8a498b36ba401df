"""Topic key expressions per distribution, pinned to rmw_zenoh's sources and examples.

Sources (``REL`` is ros2-gbp/rmw_zenoh-release, the files at its root):
- jazzy REL@d38ea19c src/detail/liveliness_utils.cpp:86-93 builds the key as
  ``domain/strip_slashes(topic)/type/hash``; kilted REL@70c38f56 is the same file.
- humble REL@79eeaa2d src/detail/rmw_publisher_data.cpp:75 writes "TypeHashNotSupported".
- ros2/rmw_zenoh@99a6a2bd docs/design.md ("Topic and Service name mapping to Zenoh key
  expressions") gives the chatter examples below.
"""

from __future__ import annotations

import pytest

from ego.errors import FrameError, OutOfRangeError, UnknownDeviceError
from ego.ros2 import dds_type_name, parse_topic_key, resolve_topic, ros_type_name, topic_key
from ego.ros2.keys import TopicKey
from ego.ros2.messages import type_hash

STRING_HASH = "RIHS01_df668c740482bbd48fb39d76a70dfd4bd59db1288021743503259e948f6b1a18"


@pytest.mark.parametrize("distro", ["jazzy", "kilted"])
def test_the_chatter_keys_of_rmw_zenohs_design_document(distro: str) -> None:
    # design.md: "0/chatter/std_msgs::msg::dds_::String_/RIHS01_df668c74…6b1a18"
    hash_ = type_hash("std_msgs/msg/String", distro)
    assert topic_key(0, "/chatter", "std_msgs/msg/String", hash_, distro) == (
        "0/chatter/std_msgs::msg::dds_::String_/" + STRING_HASH
    )
    # design.md: the same topic in the /robot1 namespace keeps its inner slash.
    topic = resolve_topic("chatter", namespace="/robot1")
    assert topic_key(0, topic, "std_msgs/msg/String", STRING_HASH, distro) == (
        "0/robot1/chatter/std_msgs::msg::dds_::String_/" + STRING_HASH
    )


def test_humble_keys_end_in_type_hash_not_supported() -> None:
    # humble rmw_publisher_data.cpp:75: const char * type_hash_c_str = "TypeHashNotSupported";
    hash_ = type_hash("sensor_msgs/msg/Range", "humble")
    assert topic_key(3, "/robot/ps0", "sensor_msgs/msg/Range", hash_, "humble") == (
        "3/robot/ps0/sensor_msgs::msg::dds_::Range_/TypeHashNotSupported"
    )


def test_a_key_parses_back_to_its_parts() -> None:
    key = "0/robot/gs0/sensor_msgs::msg::dds_::Range_/" + "RIHS01_" + "ab" * 32
    assert parse_topic_key(key, "jazzy") == TopicKey(
        0, "/robot/gs0", "sensor_msgs/msg/Range", "RIHS01_" + "ab" * 32
    )
    assert str(parse_topic_key(key, "jazzy")) == key


def test_relative_private_and_absolute_names_resolve_as_rcl_does() -> None:
    assert resolve_topic("ps0", namespace="/robot") == "/robot/ps0"
    assert resolve_topic("/gs0", namespace="/robot") == "/gs0"  # epuck_ros2 driver.cpp:154
    assert resolve_topic("~/status", namespace="/robot", node="epuck") == "/robot/epuck/status"
    assert resolve_topic("image_raw/compressed") == "/image_raw/compressed"


def test_dds_type_names_go_both_ways() -> None:
    # type_support_common.cpp:39-48: namespace "::" then "dds_::" name "_"
    assert dds_type_name("tf2_msgs/msg/TFMessage") == "tf2_msgs::msg::dds_::TFMessage_"
    assert ros_type_name("tf2_msgs::msg::dds_::TFMessage_") == "tf2_msgs/msg/TFMessage"


@pytest.mark.parametrize(
    ("call", "error", "message"),
    [
        (lambda: topic_key(0, "chatter", "std_msgs/msg/String", STRING_HASH, "jazzy"),
         FrameError, "topic name 'chatter' must be absolute"),
        (lambda: topic_key(0, "/a//b", "std_msgs/msg/String", STRING_HASH, "jazzy"),
         FrameError, "token '' is not letters"),
        (lambda: topic_key(0, "/1abc", "std_msgs/msg/String", STRING_HASH, "jazzy"),
         FrameError, "token '1abc'"),
        (lambda: topic_key(-1, "/a", "std_msgs/msg/String", STRING_HASH, "jazzy"),
         OutOfRangeError, "domain id -1 is outside"),
        (lambda: topic_key(0, "/a", "std_msgs/String", STRING_HASH, "jazzy"),
         FrameError, "'std_msgs/String' is not 'package/msg/Name'"),
        (lambda: topic_key(0, "/a", "std_msgs/msg/String", STRING_HASH, "humble"),
         FrameError, "is not what humble writes ('TypeHashNotSupported')"),
        (lambda: topic_key(0, "/a", "std_msgs/msg/String", "TypeHashNotSupported", "jazzy"),
         FrameError, "is not what jazzy writes"),
        (lambda: topic_key(0, "/a", "std_msgs/msg/String", STRING_HASH, "rolling"),
         UnknownDeviceError, "'rolling' is not one ego speaks (known: humble, jazzy, kilted)"),
        (lambda: parse_topic_key("0/chatter/" + STRING_HASH, "jazzy"),
         FrameError, "is not 'domain/topic/type/hash'"),
        (lambda: parse_topic_key("x/chatter/std_msgs::msg::dds_::String_/" + STRING_HASH, "jazzy"),
         FrameError, "domain 'x' is not a domain id"),
        (lambda: parse_topic_key("0/chatter/std_msgs::msg::String/" + STRING_HASH, "jazzy"),
         FrameError, "is not 'package::msg::dds_::Name_'"),
        (lambda: parse_topic_key("0/" + "a/" * 3000 + "T/h", "jazzy"),
         FrameError, "topic key of 6005 characters (at most 4096)"),
    ],
)  # fmt: skip
def test_bad_names_keys_and_hashes_are_refused_in_one_line(
    call: object, error: type[Exception], message: str
) -> None:
    with pytest.raises(error) as caught:
        call()  # type: ignore[operator]
    assert message in str(caught.value) and "\n" not in str(caught.value)
