"""Reading a ROS 2 recording back as ego's own: what ``ego replay`` and ``ego plot`` need.

A ROS 2 recording (:mod:`ego.recording.ros2_bag`) keeps ego's channels, their JSON in a
``std_msgs/msg/String``, and the camera's frames as ``/image_raw/compressed``. Here those
become the messages of a JSON recording (the frames its ``/camera/image``), so that
:class:`~ego.recording.reader.Recording` reads both flavours the same way; the ROS 2
topics are for ROS 2 tools, and left as they are. The CDR is read by rosbags (the
``ros2`` extra: one line naming it if it is missing).
"""

from __future__ import annotations

import base64
import json

from ego.errors import EgoError, RecordingError
from ego.recording.records import RawMessage, RawRecording
from ego.recording.ros2_bag import EGO_STRING_TOPICS
from ego.recording.schemas import CHANNELS

__all__ = ["from_ros2"]

_FRAMES = "/image_raw/compressed"


def from_ros2(raw: RawRecording, name: str, distro: str) -> RawRecording:
    """``raw`` (a ROS 2 recording of ``distro``) with ego's channels as JSON ones."""
    from ego.ros2.messages import decode_message

    out = RawRecording(metadata=raw.metadata)
    for topic in (*EGO_STRING_TOPICS, "/camera/image"):
        out.schemas[topic] = CHANNELS[topic]
    for topic, schema in raw.schemas.items():
        if topic in EGO_STRING_TOPICS and schema != "std_msgs/msg/String":
            raise RecordingError(f"{name}: channel {topic} carries {schema or 'no schema'!r}, "
                                 "not 'std_msgs/msg/String'")  # fmt: skip
    for message in raw.messages:
        try:
            if message.topic in EGO_STRING_TOPICS:
                text = decode_message(message.data, "std_msgs/msg/String", distro).data
                out.messages.append(RawMessage(message.topic, message.log_time, text.encode()))
            elif message.topic == _FRAMES:
                jpeg = bytes(decode_message(message.data, "sensor_msgs/msg/CompressedImage",
                                            distro).data)  # fmt: skip
                frame = {"data": base64.b64encode(jpeg).decode("ascii")}
                out.messages.append(RawMessage("/camera/image", message.log_time,
                                               json.dumps(frame).encode()))  # fmt: skip
        except EgoError as exc:
            if "ego[ros2]" in str(exc):
                raise  # the extra is missing: its own line
            raise RecordingError(f"{name}: a message on {message.topic}: {exc}") from exc
    return out
