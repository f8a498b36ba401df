"""The attachment: pinned bytes per distribution, and zenoh-ext's own serializer as the
second implementation that reads what ego writes and writes what ego reads.

Sources (REL is ros2-gbp/rmw_zenoh-release):
- jazzy REL@d38ea19c src/detail/attachment_helpers.cpp:67-74: ``serialize(sequence_number_);
  serialize(source_timestamp_); serialize(source_gid_)``, the GID a
  ``std::array<uint8_t, RMW_GID_STORAGE_SIZE>`` (16, ros2/rmw@c90c2970 rmw/types.h:44);
  kilted REL@70c38f56 is the same file.
- humble REL@79eeaa2d src/detail/attachment_helpers.cpp:35,81: ``std::array<uint8_t, 16>``.
- eclipse-zenoh/roadmap rfcs/ALL/Serialization.md: int64 little-endian; an array as a
  LEB128 length, then its bytes.
"""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st
from zenoh import ZBytes
from zenoh.ext import Int64, z_deserialize, z_serialize

from ego.errors import FrameError, OutOfRangeError
from ego.ros2 import Attachment, attachment_size, decode_attachment, encode_attachment

DISTROS = ["humble", "jazzy", "kilted"]
INT64 = st.integers(-(2**63), 2**63 - 1)


@pytest.mark.parametrize("distro", DISTROS)
def test_the_attachment_is_33_bytes_seq_stamp_then_a_length_prefixed_gid(distro: str) -> None:
    data = encode_attachment(Attachment(7, 0x0102030405060708, bytes(range(16))), distro)
    # seq 7 as int64 LE | stamp as int64 LE | LEB128 16 | the 16 GID bytes
    assert data.hex(" ") == (
        "07 00 00 00 00 00 00 00 08 07 06 05 04 03 02 01 10 "
        "00 01 02 03 04 05 06 07 08 09 0a 0b 0c 0d 0e 0f"
    )
    assert attachment_size(distro) == len(data) == 33


@pytest.mark.parametrize("distro", DISTROS)
@given(seq=INT64, stamp=INT64, gid=st.binary(min_size=16, max_size=16))
def test_zenoh_ext_reads_what_ego_writes(distro: str, seq: int, stamp: int, gid: bytes) -> None:
    data = encode_attachment(Attachment(seq, stamp, gid), distro)
    assert z_deserialize(tuple[Int64, Int64, bytes], ZBytes(data)) == (seq, stamp, gid)


@pytest.mark.parametrize("distro", DISTROS)
@given(seq=INT64, stamp=INT64, gid=st.binary(min_size=16, max_size=16))
def test_ego_reads_what_zenoh_ext_writes(distro: str, seq: int, stamp: int, gid: bytes) -> None:
    data = z_serialize((Int64(seq), Int64(stamp), gid)).to_bytes()
    assert decode_attachment(data, distro) == Attachment(seq, stamp, gid)


@given(data=st.binary(max_size=64))
def test_random_bytes_decode_or_are_refused_as_frames(data: bytes) -> None:
    try:
        decoded = decode_attachment(data, "jazzy")
    except FrameError:
        return
    assert encode_attachment(decoded, "jazzy") == data


@pytest.mark.parametrize(
    ("call", "error", "message"),
    [
        (lambda: decode_attachment(bytes(32), "jazzy"), FrameError,
         "attachment of 32 bytes: jazzy sends 33"),
        (lambda: decode_attachment(bytes(16) + b"\x0f" + bytes(16), "humble"), FrameError,
         "attachment GID length prefix 0f is not 10 (16 bytes)"),
        (lambda: encode_attachment(Attachment(1, 2, bytes(24)), "humble"), OutOfRangeError,
         "GID of 24 bytes: humble wants 16"),
        (lambda: encode_attachment(Attachment(2**63, 0, bytes(16)), "jazzy"), OutOfRangeError,
         "attachment sequence number 9223372036854775808 does not fit an int64"),
        (lambda: encode_attachment(Attachment(1, 1.5, bytes(16)), "jazzy"), TypeError,  # type: ignore[arg-type]
         "attachment source timestamp must be an int, not float"),
    ],
)  # fmt: skip
def test_bad_attachments_are_refused_in_one_line(
    call: object, error: type[Exception], message: str
) -> None:
    with pytest.raises(error) as caught:
        call()  # type: ignore[operator]
    assert str(caught.value) == message
