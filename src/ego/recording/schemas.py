"""The channels of an ego recording and their JSON schemas.

Where Foxglove has a well-known schema for what a channel carries, the channel uses it
under its Foxglove name (``foxglove.CompressedImage``, ``foxglove.PoseInFrame``,
``foxglove.Log``), JSON-encoded, so that Foxglove shows a run's camera, paths and link
events as they are; the schemas below follow Foxglove's published field definitions
(docs.foxglove.dev, "Message schemas"). ego's own channels carry ego's names.
"""

from __future__ import annotations

import json
import math
from typing import Any

from ego.devices.table import TABLE, DeviceTable

__all__ = [
    "CHANNELS",
    "SCHEMAS",
    "log_message",
    "pose_message",
    "schema_bytes",
    "sensors_schema",
    "stamp",
]

_TIME = {
    "type": "object",
    "properties": {"sec": {"type": "integer"}, "nsec": {"type": "integer"}},
}
_VECTOR3 = {"type": "object", "properties": {k: {"type": "number"} for k in "xyz"}}
_QUATERNION = {"type": "object", "properties": {k: {"type": "number"} for k in "xyzw"}}



def sensors_schema(table: DeviceTable = TABLE) -> dict[str, Any]:
    """``ego.Sensors``: one step of the robot, with each family the table samples."""
    readings = {"type": ["array", "null"], "items": {"type": "number"}}
    return {
        "title": "ego.Sensors",
        "description": "One step of the robot (ego.core.telemetry): every family's last sample "
        "(null when off), the wheel speeds and LEDs asked, odometry, true pose, link counters",
        "type": "object",
        "properties": {
            "t": {"type": "number"},
            "step": {"type": "integer"},
            **{family.name: readings for family in table.sampled},
        },
    }


SCHEMAS: dict[str, dict[str, Any]] = {
    "foxglove.CompressedImage": {
        "title": "foxglove.CompressedImage",
        "type": "object",
        "properties": {
            "timestamp": _TIME,
            "frame_id": {"type": "string"},
            "data": {"type": "string", "contentEncoding": "base64"},
            "format": {"type": "string"},
        },
    },
    "foxglove.PoseInFrame": {
        "title": "foxglove.PoseInFrame",
        "type": "object",
        "properties": {
            "timestamp": _TIME,
            "frame_id": {"type": "string"},
            "pose": {
                "type": "object",
                "properties": {"position": _VECTOR3, "orientation": _QUATERNION},
            },
        },
    },
    "foxglove.Log": {
        "title": "foxglove.Log",
        "type": "object",
        "properties": {
            "timestamp": _TIME,
            "level": {"type": "integer", "description": "1 debug, 2 info, 3 warning, 4 error"},
            "message": {"type": "string"},
            "name": {"type": "string"},
            "file": {"type": "string"},
            "line": {"type": "integer"},
        },
    },
    "ego.Sensors": sensors_schema(),
    "ego.Exchange": {
        "title": "ego.Exchange",
        "description": "One batch on the wire: the bytes sent and the reply, base64",
        "type": "object",
        "properties": {
            "step": {"type": "integer"},
            "t": {"type": "number"},
            "tx": {"type": "string", "contentEncoding": "base64"},
            "rx": {"type": "string", "contentEncoding": "base64"},
        },
    },
}

#: Topic -> schema name, in the order they are registered.
CHANNELS: dict[str, str] = {
    "/ego/sensors": "ego.Sensors",
    "/ego/exchange": "ego.Exchange",
    "/camera/image": "foxglove.CompressedImage",
    "/ego/pose/odometry": "foxglove.PoseInFrame",
    "/ego/pose/truth": "foxglove.PoseInFrame",
    "/ego/log": "foxglove.Log",
}


def schema_bytes(name: str) -> bytes:
    return json.dumps(SCHEMAS[name]).encode()


def stamp(time_ns: int) -> dict[str, int]:
    return {"sec": time_ns // 1_000_000_000, "nsec": time_ns % 1_000_000_000}


def pose_message(time_ns: int, pose: list[float]) -> dict[str, Any]:
    """A planar pose [x, y, theta] as a foxglove.PoseInFrame in the world frame."""
    x, y, theta = pose
    return {
        "timestamp": stamp(time_ns),
        "frame_id": "world",
        "pose": {
            "position": {"x": x, "y": y, "z": 0.0},
            "orientation": {"x": 0.0, "y": 0.0, "z": math.sin(theta / 2), "w": math.cos(theta / 2)},
        },
    }


def log_message(time_ns: int, level: int, message: str) -> dict[str, Any]:
    return {"timestamp": stamp(time_ns), "level": level, "message": message, "name": "ego",
            "file": "", "line": 0}  # fmt: skip
