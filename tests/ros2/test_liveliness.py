"""Liveliness tokens, their QoS field and the GID, pinned to rmw_zenoh per distribution.

Sources (REL is ros2-gbp/rmw_zenoh-release; jazzy REL@d38ea19c, kilted REL@70c38f56,
humble REL@79eeaa2d):
- src/detail/liveliness_utils.cpp: jazzy :449-478 (humble :396-425) joins admin space,
  domain, zid, node id, entity id, kind, mangled enclave, namespace and node name, then
  mangled topic, type, hash and the QoS field; jazzy :290-351 (humble :237-299) writes
  the QoS field, a value left empty where it equals the default of src/detail/qos.cpp:18-33.
- ros2/rmw_zenoh@99a6a2bd docs/design.md ("Graph Cache"): the listener/talker examples.
- The GID: jazzy liveliness_utils.cpp:489-493, XXH3-128 of the key, low64 then high64.
"""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from ego.errors import FrameError, OutOfRangeError
from ego.ros2 import (
    SENSOR_DATA,
    EntityKind,
    NodeInfo,
    QoS,
    Token,
    TopicInfo,
    graph_key,
    keyexpr_to_qos,
    node_token,
    parse_token,
    publisher_token,
    qos_to_keyexpr,
    subscription_token,
)
from ego.ros2.gid import entity_gid
from ego.ros2.qos import (
    INFINITE,
    Durability,
    Duration,
    History,
    Liveliness,
    Reliability,
    adapt,
)

STRING_HASH = "RIHS01_df668c740482bbd48fb39d76a70dfd4bd59db1288021743503259e948f6b1a18"
PREFIX = "@ros2_lv/0/ab/0/1/MP/%/%/n/%t/std_msgs::msg::dds_::String_/" + STRING_HASH
CHATTER = "%chatter/std_msgs::msg::dds_::String_/"


def listener(zid: str = "aac3178e146ba6f1fc6e6a4085e77f21") -> NodeInfo:
    return NodeInfo(domain_id=2, zid=zid, node_id=0, name="listener")


@pytest.mark.parametrize("distro", ["jazzy", "kilted"])
def test_the_listener_and_talker_tokens_of_rmw_zenohs_design_document(distro: str) -> None:
    # design.md: "@ros2_lv/2/aac3178e146ba6f1fc6e6a4085e77f21/0/0/NN/%/%/listener"
    assert node_token(listener(), distro) == (
        "@ros2_lv/2/aac3178e146ba6f1fc6e6a4085e77f21/0/0/NN/%/%/listener"
    )
    # design.md: ".../0/10/MS/%/%/listener/%chatter/std_msgs::msg::dds_::String_/RIHS01_…/
    # ::,10:,:,:,,"
    chatter = TopicInfo("/chatter", "std_msgs/msg/String", STRING_HASH, QoS(depth=10))
    assert subscription_token(listener(), 10, chatter, distro) == (
        "@ros2_lv/2/aac3178e146ba6f1fc6e6a4085e77f21/0/10/MS/%/%/listener/"
        + CHATTER + STRING_HASH + "/::,10:,:,:,,"
    )  # fmt: skip
    # design.md: the talker's publisher, depth 7: ".../0/10/MP/%/%/talker/…/::,7:,:,:,,"
    talker = NodeInfo(2, "8b20917502ee955ac4476e0266340d5c", 0, "talker")
    chatter7 = TopicInfo("/chatter", "std_msgs/msg/String", STRING_HASH, QoS(depth=7))
    assert publisher_token(talker, 10, chatter7, distro) == (
        "@ros2_lv/2/8b20917502ee955ac4476e0266340d5c/0/10/MP/%/%/talker/"
        + CHATTER + STRING_HASH + "/::,7:,:,:,,"
    )  # fmt: skip


def test_humble_tokens_carry_type_hash_not_supported_and_namespaces_mangled() -> None:
    node = NodeInfo(0, "1f", 1, "epuck", namespace="/robot")
    ps0 = TopicInfo("/robot/ps0", "sensor_msgs/msg/Range", "TypeHashNotSupported", SENSOR_DATA)
    assert publisher_token(node, 4, ps0, "humble") == (
        "@ros2_lv/0/1f/1/4/MP/%/%robot/epuck/%robot%ps0/sensor_msgs::msg::dds_::Range_/"
        "TypeHashNotSupported/2::,5:,:,:,,"
    )
    assert node_token(node, "humble") == "@ros2_lv/0/1f/1/1/NN/%/%robot/epuck"


def test_tokens_parse_back_to_what_made_them() -> None:
    node = NodeInfo(7, "abc", 3, "epuck", namespace="/a/b", enclave="/secure")
    topic = TopicInfo("/a/b/odom", "nav_msgs/msg/Odometry", "RIHS01_" + "0" * 64, QoS(depth=1))
    key = subscription_token(node, 9, topic, "kilted")
    assert parse_token(key, "kilted") == Token(EntityKind.SUBSCRIPTION, node, 9, topic)
    assert parse_token(node_token(node, "kilted"), "kilted") == Token(EntityKind.NODE, node, 3)
    assert graph_key(7) == "@ros2_lv/7/**"  # liveliness_utils.cpp:428-432


def test_an_explicit_profile_leaves_exactly_rmw_zenohs_defaults_empty() -> None:
    # qos.cpp:18-33: KEEP_LAST, depth 42, RELIABLE, VOLATILE, infinite durations, AUTOMATIC.
    explicit = QoS(
        Reliability.RELIABLE, Durability.VOLATILE, History.KEEP_LAST, 42,
        INFINITE, INFINITE, Liveliness.AUTOMATIC, INFINITE,
    )  # fmt: skip
    assert qos_to_keyexpr(explicit, "kilted") == "::,:,:,:,,"
    rclcpp_default = QoS(Reliability.RELIABLE, Durability.VOLATILE, History.KEEP_LAST, 10)
    assert qos_to_keyexpr(rclcpp_default, "jazzy") == "::,10:,:,:,,"  # design.md
    assert INFINITE == (9223372036, 854775807)  # RMW_DURATION_INFINITE, rmw/time.h:54


def test_the_epuck_drivers_publishers_show_as_depth_1_reliable_volatile() -> None:
    # cyberbotics/epuck_ros2@91ff8a1f epuck_ros2_driver/src/driver.cpp:157:
    # create_publisher<sensor_msgs::msg::Range>("ps" + std::to_string(i), 1): rclcpp's
    # KeepLast(1), reliable, volatile.
    node = NodeInfo(0, "1f", 0, "EPuckDriver")
    ps0 = TopicInfo("/ps0", "sensor_msgs/msg/Range", "RIHS01_" + "1" * 64, QoS(depth=1))
    assert publisher_token(node, 5, ps0, "jazzy").endswith(
        "/%ps0/sensor_msgs::msg::dds_::Range_/RIHS01_" + "1" * 64 + "/::,1:,:,:,,"
    )


@pytest.mark.parametrize(
    ("qos", "field"),
    [
        (QoS(), "::,:,:,:,,"),  # every value rmw_zenoh's default
        (QoS(depth=10), "::,10:,:,:,,"),  # rclcpp's default profile (design.md)
        (SENSOR_DATA, "2::,5:,:,:,,"),  # best effort, depth 5
        (QoS(durability=Durability.TRANSIENT_LOCAL, depth=1), ":1:,1:,:,:,,"),  # /tf_static
        (QoS(history=History.KEEP_ALL), "::2,:,:,:,,"),
        (QoS(deadline=Duration(1, 500), lifespan=Duration(0, 0)), "::,:1,500:,:,,"),
        (QoS(liveliness=Liveliness.MANUAL_BY_TOPIC, lease=Duration(2, 0)), "::,:,:,:3,2,0"),
        # System defaults and unspecified durations become rmw_zenoh's (best_available_qos).
        (QoS(reliability=0, durability=0, history=0, depth=0, deadline=Duration(0, 0)),
         "::,:,:,:,,"),
    ],
)  # fmt: skip
def test_the_qos_field_leaves_defaults_empty(qos: QoS, field: str) -> None:
    assert qos_to_keyexpr(qos, "jazzy") == qos_to_keyexpr(qos, "humble") == field
    back = keyexpr_to_qos(field, "jazzy")
    assert qos_to_keyexpr(back, "jazzy") == field


def test_best_available_exists_from_jazzy_on_only() -> None:
    qos = QoS(reliability=Reliability.BEST_AVAILABLE)
    assert qos_to_keyexpr(qos, "jazzy") == "4::,:,:,:,,"
    with pytest.raises(OutOfRangeError, match="QoS reliability 4 is not one humble knows"):
        qos_to_keyexpr(qos, "humble")
    with pytest.raises(FrameError, match="QoS reliability 4 is not one humble knows"):
        keyexpr_to_qos("4::,:,:,:,,", "humble")


@given(
    rel=st.sampled_from([1, 2, 4]), dur=st.sampled_from([1, 2, 4]), hist=st.sampled_from([1, 2]),
    depth=st.integers(1, 2**32), sec=st.integers(0, 2**40), nsec=st.integers(0, 10**9),
)  # fmt: skip
def test_qos_fields_round_trip(
    rel: int, dur: int, hist: int, depth: int, sec: int, nsec: int
) -> None:
    qos = QoS(
        rel, dur, hist, depth, Duration(sec, nsec), Duration(nsec, sec), 1, Duration(sec, sec)
    )
    # Zero durations are "unspecified": rmw_zenoh writes its defaults for them (adapt).
    assert keyexpr_to_qos(qos_to_keyexpr(qos, "kilted"), "kilted") == adapt(qos)


def test_the_gid_is_rmw_zenohs_xxh3_of_the_token() -> None:
    # Pinned by compiling jazzy src/detail/simplified_xxhash3.cpp (not kept) with a main()
    # copying low64 then high64, as liveliness_utils.cpp:489-493 does, for this key.
    key = (
        "@ros2_lv/0/1234567890abcdef1234567890abcdef/0/10/MP/%/%/epuck/%ps0/"
        "sensor_msgs::msg::dds_::Range_/RIHS01_b42b62562e93cbfe9d42b82fe5994dfa3d63d7d5c90a"
        "317981703f7388adff3a/2:2:,5:,:,:,,"
    )
    assert entity_gid(key, "jazzy").hex() == "fb7f452fbfec2a405935963f8d293e11"
    assert entity_gid("short", "humble").hex() == "89dedfe9d5127012921725952605de5a"


@pytest.mark.parametrize(
    ("key", "message"),
    [
        ("@ros2_lv/0/ab/0/0/XX/%/%/n", "kind 'XX' is not one of NN, MP, MS, SS, SC"),
        ("@ros2_lv/0/ab/0/0/NN/%/%", "is not '@ros2_lv/domain/zid/nid/id/KIND/"),
        ("@ros2_lv/0/ab/0/0/NN/%//n", "is not '@ros2_lv/domain/zid/nid/id/KIND/"),
        ("@ros2/0/ab/0/0/NN/%/%/n", "is not '@ros2_lv/domain/zid/nid/id/KIND/"),
        ("@ros2_lv/0/ab/x/0/NN/%/%/n", "node id 'x' is not a number"),
        ("@ros2_lv/0/AB/0/0/NN/%/%/n", "Zenoh id 'AB' is not 1..32 lowercase hex digits"),
        ("@ros2_lv/0/ab/0/0/MP/%/%/n", "MP with the wrong fields"),
        ("@ros2_lv/0/ab/0/1/MP/%/%/n/%t/std_msgs::msg::dds_::String_/" + STRING_HASH + "/::,:",
         "is not 'rel:dur:hist,depth:s,ns:s,ns:liveliness,s,ns'"),
        (PREFIX + "/x::,:,:,:,,",
         "reliability 'x' is not a number"),
        (PREFIX.replace("/1/MP/", "/0/NN/") + "/::,:,:,:,,",
         "NN with the wrong fields"),
        ("@ros2_lv/0/ab/0/1/MS/%/%/n/t/std_msgs::msg::dds_::String_/" + STRING_HASH + "/::,:,:,:,,",
         "topic name 't' must be absolute"),
    ],
)  # fmt: skip
def test_malformed_tokens_are_refused_in_one_line(key: str, message: str) -> None:
    with pytest.raises(FrameError) as caught:
        parse_token(key, "jazzy")
    assert message in str(caught.value) and "\n" not in str(caught.value)
