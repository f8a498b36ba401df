"""Whatever arrives from the network, the parsers answer with a value or a FrameError:
never another exception, so a node can drop a bad key, token or payload and go on."""

from __future__ import annotations

from typing import Any

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from ego.errors import FrameError
from ego.ros2 import keyexpr_to_qos, parse_token, parse_topic_key
from ego.ros2.messages import EPUCK_TYPES, decode_message, encode_message, message_class, typestore

HASH = "RIHS01_" + "ab" * 32
#: Pieces of real keys and tokens, so that random joins reach the parsers' deeper checks.
PIECES = ["@ros2_lv", "0", "4294967296", "99999999999999999999", "ab", "AB", "1", "MP",
          "NN", "MS", "%", "%robot", "epuck", "%t", "t", "1x", "", "std_msgs::msg::dds_::String_",
          "std_msgs::msg::String", HASH, "TypeHashNotSupported", "::,:,:,:,,", "2::,5:,:,:,,",
          "4::,:,:,:,,", "::,-1:,:,:,,", "::,:,:,:,", "x", "²", "%%"]  # fmt: skip
JOINED = st.lists(st.sampled_from(PIECES), max_size=15).map("/".join)
QOS_VALUES = ["", "1", "2", "4", "9", "42", "-1", "x", "18446744073709551616"]
QOS_PIECES = st.lists(st.sampled_from(QOS_VALUES), max_size=14)


def refused_or_parsed(parse: object, text: str, distro: str) -> None:
    try:
        parse(text, distro)  # type: ignore[operator]
    except FrameError as exc:
        assert "\n" not in str(exc)


@settings(max_examples=300)
@given(text=st.one_of(JOINED, st.text(max_size=80)), distro=st.sampled_from(["humble", "jazzy"]))
def test_random_tokens_and_keys_parse_or_are_frame_errors(text: str, distro: str) -> None:
    refused_or_parsed(parse_token, text, distro)
    refused_or_parsed(parse_topic_key, text, distro)


@settings(max_examples=300)
@given(parts=QOS_PIECES, seps=st.lists(st.sampled_from([":", ","]), max_size=14))
def test_random_qos_fields_parse_or_are_frame_errors(parts: list[str], seps: list[str]) -> None:
    text = "".join(p + s for p, s in zip(parts, seps + [""] * len(parts), strict=False))
    refused_or_parsed(keyexpr_to_qos, text, "kilted")


@settings(max_examples=200)
@given(
    type_name=st.sampled_from(EPUCK_TYPES),
    cut=st.integers(0, 200),
    noise=st.binary(max_size=64),
)
def test_cut_or_noisy_payloads_decode_or_are_frame_errors(
    type_name: str, cut: int, noise: bytes
) -> None:
    whole = encode_message(_default(message_class(type_name, "jazzy"), "jazzy"), "jazzy")
    for payload in (whole[:cut], whole[:4] + noise, noise):
        try:
            decode_message(payload, type_name, "jazzy")
        except FrameError as exc:
            assert "\n" not in str(exc)


def _default(cls: Any, distro: str) -> Any:
    """A message of ``cls`` with zeros, empty strings and empty sequences."""
    values: dict[str, Any] = {}
    for name, desc in typestore(distro).fielddefs[cls.__msgtype__][1]:
        kind, rest = int(desc[0]), desc[1]  # rosbags' Nodetype: 1 base, 2 name, 3 array, 4 seq
        if kind == 2:
            values[name] = _default(message_class(rest, distro), distro)
        elif kind == 1:
            values[name] = {"string": "", "bool": False}.get(rest[0], 0)
        elif int(rest[0][0]) == 1 and rest[0][1][0] not in ("string", "bool"):
            dtype = {"byte": "uint8", "char": "uint8"}.get(rest[0][1][0], rest[0][1][0])
            values[name] = np.zeros(rest[1] if kind == 3 else 0, dtype=dtype)
        else:
            values[name] = []
    return cls(**values)
