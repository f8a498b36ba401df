"""Independent checks for the ego.ros2 tests: a minimal CDR reader and writer written from
the OMG CDR rules, and REP-2011's RIHS01 hash written from rosidl's generator, neither
using rosbags (which ego.ros2 uses), so each test meets ego with a second implementation.

Sources:
- CDR (XCDR1, "plain CDR"): OMG DDS-XTypes 1.3 §7.4.1 / CORBA 3.3 part 2 §9.3: primitives
  aligned to their size, counted from the byte after the 4-byte encapsulation header;
  a string is a uint32 length counting its NUL, the bytes, then the NUL; a sequence is a
  uint32 count then its elements.
- RIHS01: REP-2011 and ros2/rosidl rosidl_generator_type_description/__init__.py
  (``calculate_type_hash``): sha256 of ``json.dumps`` (separators ``', '`` and ``': '``) of
  ``{"type_description": ..., "referenced_type_descriptions": [... sorted by type_name]}``,
  fields as ``{"name", "type": {"type_id", "capacity", "string_capacity",
  "nested_type_name"}}``, default values left out; type ids from
  type_description_interfaces/msg/FieldType.msg (arrays +48, bounded sequences +96,
  unbounded sequences +144); an empty message gets the field
  ``structure_needs_at_least_one_member`` of uint8.
"""

from __future__ import annotations

import hashlib
import json
import re
import socket
import struct
from collections.abc import Callable, Mapping
from typing import Any

# -- CDR -----------------------------------------------------------------------------------

_FORMATS = {"int8": "b", "uint8": "B", "bool": "?", "byte": "B", "char": "B",
            "int16": "h", "uint16": "H", "int32": "i", "uint32": "I",
            "int64": "q", "uint64": "Q", "float32": "f", "float64": "d"}  # fmt: skip


class CdrReader:
    """Reads little-endian plain CDR after checking the encapsulation header 00 01 00 00."""

    def __init__(self, payload: bytes) -> None:
        assert payload[:4] == b"\x00\x01\x00\x00", payload[:4].hex()
        self.data = payload[4:]
        self.at = 0

    def read(self, kind: str) -> Any:
        fmt = struct.Struct("<" + _FORMATS[kind])
        self.at += -self.at % fmt.size
        (value,) = fmt.unpack_from(self.data, self.at)
        self.at += fmt.size
        return value

    def string(self) -> str:
        n = self.read("uint32")
        raw = self.data[self.at : self.at + n]
        self.at += n
        assert raw.endswith(b"\x00")
        return raw[:-1].decode()

    def sequence(self, kind: str) -> list[Any]:
        return [self.read(kind) for _ in range(self.read("uint32"))]

    def array(self, kind: str, count: int) -> list[Any]:
        return [self.read(kind) for _ in range(count)]

    def done(self) -> bool:
        """True when every byte was read (XCDR1 may pad the end to 4 bytes: zeros only)."""
        rest = self.data[self.at :]
        return len(rest) < 4 and not any(rest)


class CdrWriter:
    """Writes little-endian plain CDR behind the encapsulation header 00 01 00 00."""

    def __init__(self) -> None:
        self.data = bytearray()

    def write(self, kind: str, value: Any) -> CdrWriter:
        fmt = struct.Struct("<" + _FORMATS[kind])
        self.data += bytes(-len(self.data) % fmt.size)
        self.data += fmt.pack(value)
        return self

    def string(self, text: str) -> CdrWriter:
        raw = text.encode() + b"\x00"
        self.write("uint32", len(raw))
        self.data += raw
        return self

    def payload(self) -> bytes:
        return b"\x00\x01\x00\x00" + bytes(self.data)


# -- RIHS01 --------------------------------------------------------------------------------

#: type_description_interfaces/msg/FieldType.msg
TYPE_IDS = {"nested": 1, "int8": 2, "uint8": 3, "int16": 4, "uint16": 5, "int32": 6,
            "uint32": 7, "int64": 8, "uint64": 9, "float32": 10, "float64": 11,
            "char": 13, "bool": 15, "byte": 16, "string": 17, "wstring": 18,
            "bounded_string": 21}  # fmt: skip
_FIELD = re.compile(
    r"(?P<type>[\w/]+?)(?P<bound><=\d+)?(?P<arr>\[(?P<n><=)?(?P<cap>\d*)\])?\s+(?P<name>\w+)"
)


def field_entry(type_text: str, name: str, package: str) -> dict[str, Any]:
    """One field of a type description, from a .msg line's type and name."""
    match = _FIELD.fullmatch(f"{type_text} {name}")
    assert match, type_text
    base, capacity, string_capacity, nested = match["type"], 0, 0, ""
    if base in TYPE_IDS:
        tid = TYPE_IDS[base]
    elif base == "string" or match["bound"]:
        tid = TYPE_IDS["string"]
    else:
        tid = TYPE_IDS["nested"]
        pkg, _, short = base.rpartition("/")
        nested = base if base.count("/") == 2 else f"{pkg or package}/msg/{short}"
        if base == "Header":
            nested = "std_msgs/msg/Header"
    if match["bound"]:
        tid, string_capacity = TYPE_IDS["bounded_string"], int(match["bound"][2:])
    if match["arr"] is not None:
        if match["n"]:
            tid, capacity = tid + 96, int(match["cap"])
        elif match["cap"]:
            tid, capacity = tid + 48, int(match["cap"])
        else:
            tid += 144
    type_ = {"type_id": tid, "capacity": capacity, "string_capacity": string_capacity,
             "nested_type_name": nested}  # fmt: skip
    return {"name": name, "type": type_}


def describe(type_name: str, msg_text: str) -> dict[str, Any]:
    """The type description of ``type_name`` from its .msg text (constants skipped)."""
    package = type_name.split("/")[0]
    fields = []
    for line in msg_text.splitlines():
        line = line.split("#")[0].strip()
        if not line or "=" in line:  # blank, or a constant (NAME=VALUE)
            continue
        type_text, name = line.split()[:2]  # a third token is a default value
        fields.append(field_entry(type_text, name, package))
    if not fields:
        fields.append(field_entry("uint8", "structure_needs_at_least_one_member", package))
    return {"type_name": type_name, "fields": fields}


def rihs01(type_name: str, describe_type: Callable[[str], Mapping[str, Any]]) -> str:
    """REP-2011's hash of ``type_name``; ``describe_type`` gives any type's description."""
    seen: dict[str, Mapping[str, Any]] = {}

    def walk(name: str) -> None:
        if name in seen:
            return
        seen[name] = describe_type(name)
        for field in seen[name]["fields"]:
            if field["type"]["nested_type_name"]:
                walk(field["type"]["nested_type_name"])

    walk(type_name)
    doc = {
        "type_description": seen[type_name],
        "referenced_type_descriptions": [seen[n] for n in sorted(seen) if n != type_name],
    }
    text = json.dumps(doc, separators=(", ", ": "), ensure_ascii=True, allow_nan=False)
    return "RIHS01_" + hashlib.sha256(text.encode("utf-8")).hexdigest()


# -- loopback ------------------------------------------------------------------------------


def free_endpoint() -> str:
    """A Zenoh TCP endpoint on a loopback port free right now."""
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return f"tcp/127.0.0.1:{probe.getsockname()[1]}"
