"""The ROS 2 flavour of a recording (``ego run --record run.mcap --record-format ros2``).

An MCAP file as rosbag2's MCAP storage writes one, so that ``ros2 bag play run.mcap``,
Foxglove and rosbags' reader open it. Read in ``ros2/rosbag2``, ``rosbag2_storage_mcap/
src/mcap_storage.cpp`` at the branches' heads: humble ``d256a5bad515cae54c5274edf1a870e3ee8668b2``
(H) and jazzy ``64717ee802a29b15acdcecd36f3f8ef286ad18b8`` (J; Kilted's branch is not in
that mirror: ego writes Jazzy's format for it):

- the header's profile is ``ros2``: ``mcap::McapWriterOptions("ros2")`` (H :91, J :97);
  rosbags' reader refuses any other (``rosbags/rosbag2/storage_mcap.py``, ``McapReader._open``);
- one schema a type: name ``pkg/msg/Name``, encoding ``ros2msg`` (H :748, J :916), data
  the ``.msg`` text with each dependency after a line of 80 ``=`` and ``MSG: pkg/Name``,
  as rosbags' ``Typestore.generate_msgdef(..., ros_version=2)`` makes it for its own
  rosbag2 writer; a channel without a schema is refused (J :470-473);
- one channel a topic, message encoding ``cdr``; its metadata ``offered_qos_profiles``
  (YAML; H stores the string for its player, J :483-488 parses it and reads either form)
  and, from J on, ``topic_type_hash`` (J :935-938, the RIHS01 hash);
- every channel CDR: rosbag2's reader refuses a bag whose topics have different
  serialization formats (``rosbag2_cpp/src/rosbag2_cpp/readers/sequential_reader.cpp``
  J :315-322, ``check_topics_serialization_formats``);
- a metadata record ``rosbag2``: H writes ``ROS_DISTRO`` in it (H :807-817,
  ``ensure_rosdistro_metadata_added``); J writes and reads ``serialized_metadata``, the
  bag's metadata YAML of version 9 (J :414-451, :956-965; the fields its decoder requires,
  ``custom_data`` a map, in ``rosbag2_storage/include/rosbag2_storage/yaml.hpp`` J :277-307);
- messages in CDR with the encapsulation header (:mod:`ego.ros2.messages`).

So ego's own channels, which keep what ``ego replay`` needs (``/ego/exchange``,
``/ego/sensors``, ``/ego/log``), carry their JSON as a ``std_msgs/msg/String`` here,
and the camera's frames are ``/image_raw/compressed``. This module does no I/O: it
registers on the writer it is handed and turns steps into (channel, bytes).
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from io import StringIO
from typing import TYPE_CHECKING, Any

from ego.devices.table import CAMERA, TABLE, DeviceTable
from ego.recording.ros2_topics import Ros2Topic, StepData, ros2_topics, static_transforms
from ego.ros2.distros import Distro, distro_format
from ego.ros2.extras import missing
from ego.ros2.messages import encode_message, message_class, typestore

if TYPE_CHECKING:
    import numpy as np
    from mcap.writer import Writer

__all__ = ["EGO_STRING_TOPICS", "FORMAT", "Ros2Bag"]

#: The value of the ``format`` key in the ``ego`` metadata of a ROS 2 recording.
FORMAT = "ros2"
#: ego's channels kept in a ROS 2 recording, their JSON in a std_msgs/msg/String.
EGO_STRING_TOPICS = ("/ego/sensors", "/ego/exchange", "/ego/log")
_STRING = "std_msgs/msg/String"
#: rosbag2's metadata version written for a distribution (None: Humble's record, no YAML).
_BAG_VERSION = {Distro.HUMBLE: None, Distro.JAZZY: 9, Distro.KILTED: 9}
_CAMERA_TOPICS = (("/image_raw", "sensor_msgs/msg/Image"),
                  ("/image_raw/compressed", "sensor_msgs/msg/CompressedImage"),
                  ("/camera_info", "sensor_msgs/msg/CameraInfo"))  # fmt: skip


@dataclass
class _Channel:
    topic: str
    type_name: str
    depth: int
    latched: bool = False  # transient local, as tf2_ros's static broadcaster offers it
    id: int | None = None  # None until its first message registers it
    count: int = 0


class Ros2Bag:
    """The ROS 2 channels of one recording in ``distro`` (a name or :class:`Distro`)."""

    def __init__(self, distro: Distro | str, table: DeviceTable = TABLE) -> None:
        distro_format(distro)  # an unknown name: one line listing the known ones
        self.distro = Distro(distro)
        self.table = table
        typestore(self.distro)  # rosbags missing: one line naming the extra
        self.topics: tuple[Ros2Topic, ...] = ros2_topics(self.table)
        wanted = [(t.topic, t.type_name, 100 if t.topic == "/tf" else 1) for t in self.topics]
        if any(row.family == CAMERA for row in self.table.devices):
            wanted += [(topic, type_name, 1) for topic, type_name in _CAMERA_TOPICS]
        wanted += [(topic, _STRING, 10) for topic in EGO_STRING_TOPICS]
        self.channels = {topic: _Channel(topic, kind, depth) for topic, kind, depth in wanted}
        self._static: Ros2Topic | None = static_transforms(self.table)
        self.channels[self._static.topic] = _Channel(self._static.topic, self._static.type_name,
                                                     1, latched=True)  # fmt: skip
        self._writer: Writer | None = None
        self._schemas: dict[str, int] = {}

    # -- registering ----------------------------------------------------------------------

    def register(self, writer: Writer) -> None:
        """Register ego's channels on ``writer`` (started with :meth:`header`'s profile);
        a ROS 2 topic's channel (and its type's schema) is registered with its first
        message, so a sensor never read leaves no empty topic in ``ros2 bag info``."""
        self._writer = writer
        for topic in EGO_STRING_TOPICS:
            self._register(self.channels[topic])

    def _register(self, channel: _Channel) -> int:
        assert self._writer is not None, "register(writer) first"
        store = typestore(self.distro)
        if channel.type_name not in self._schemas:
            text, _ = store.generate_msgdef(channel.type_name, ros_version=2)
            self._schemas[channel.type_name] = self._writer.register_schema(
                channel.type_name, "ros2msg", text.encode())
        hashed = distro_format(self.distro).fixed_type_hash is None
        metadata = {
            "offered_qos_profiles": self._qos_yaml(channel.depth, channel.latched),
            "topic_type_hash": store.hash_rihs01(channel.type_name) if hashed else "",
        }
        channel.id = self._writer.register_channel(channel.topic, "cdr",
                                                   self._schemas[channel.type_name],
                                                   metadata)  # fmt: skip
        return channel.id

    @property
    def registered(self) -> list[str]:
        """The topics with a channel in the file so far."""
        return [c.topic for c in self.channels.values() if c.id is not None]

    @staticmethod
    def header(library: str) -> dict[str, str]:
        """What ``Writer.start`` takes for a ROS 2 recording."""
        return {"profile": "ros2", "library": library}

    # -- messages -------------------------------------------------------------------------

    def make(self, type_name: str, **fields: Any) -> Any:
        """A ``type_name`` message of this distribution; a field the distribution's
        definition lacks (Humble's Range has no ``variance``) is left out."""
        cls = message_class(type_name, self.distro)
        known = cls.__dataclass_fields__
        return cls(**{k: v for k, v in fields.items() if k in known})

    def _emit(self, topic: str, message: Any) -> tuple[int, bytes]:
        channel = self.channels[topic]
        if channel.id is None:
            channel.id = self._register(channel)
        channel.count += 1
        return channel.id, encode_message(message, self.distro)

    def ego(self, topic: str, message: dict[str, Any]) -> tuple[int, bytes] | None:
        """ego's JSON ``message`` on ``topic`` as a std_msgs/msg/String (None: a topic a
        ROS 2 recording leaves out, such as Foxglove's poses: /odom and /tf hold them)."""
        if topic not in EGO_STRING_TOPICS:
            return None
        return self._emit(topic, self.make(_STRING, data=json.dumps(message)))

    def step(self, sample: dict[str, Any], time_ns: int) -> list[tuple[int, bytes]]:
        """Every topic's message of one telemetry ``sample`` stamped ``time_ns``."""
        data = StepData(sample, time_ns, self.make)
        out = []
        if self._static is not None:  # the sensors' frames, once, with the first step
            out.append(self._emit(self._static.topic, self._static.build(data)))
            self._static = None
        for topic in self.topics:
            message = topic.build(data)
            if message is not None:
                out.append(self._emit(topic.topic, message))
        return out

    def frame(self, image: np.ndarray, jpeg: bytes, time_ns: int) -> list[tuple[int, bytes]]:
        """A camera frame (RGB, H×W×3) as Image, CompressedImage (its ``jpeg``) and
        CameraInfo (uncalibrated: zero intrinsics)."""
        import numpy as np

        if "/image_raw" not in self.channels:
            return []
        header = StepData({}, time_ns, self.make).header("camera")
        height, width = int(image.shape[0]), int(image.shape[1])
        raw = self.make("sensor_msgs/msg/Image", header=header, height=height, width=width,
                        encoding="rgb8", is_bigendian=0, step=width * 3,
                        data=np.ascontiguousarray(image, dtype=np.uint8).reshape(-1))  # fmt: skip
        packed = self.make("sensor_msgs/msg/CompressedImage", header=header, format="jpeg",
                           data=np.frombuffer(jpeg, dtype=np.uint8))  # fmt: skip
        roi = self.make("sensor_msgs/msg/RegionOfInterest", x_offset=0, y_offset=0, height=0,
                        width=0, do_rectify=False)  # fmt: skip
        info = self.make("sensor_msgs/msg/CameraInfo", header=header, height=height,
                         width=width, distortion_model="", d=np.zeros(0), k=np.zeros(9),
                         r=np.zeros(9), p=np.zeros(12), binning_x=0, binning_y=0,
                         roi=roi)  # fmt: skip
        return [self._emit("/image_raw", raw), self._emit("/image_raw/compressed", packed),
                self._emit("/camera_info", info)]  # fmt: skip

    # -- the end --------------------------------------------------------------------------

    def finish(self, writer: Writer, name: str, start_ns: int, end_ns: int) -> None:
        """Add rosbag2's ``rosbag2`` metadata record, before ``writer.finish``."""
        version = _BAG_VERSION[self.distro]
        if version is None:  # Humble's: the distribution only
            writer.add_metadata("rosbag2", {"ROS_DISTRO": self.distro.value})
            return
        count = sum(c.count for c in self.channels.values())
        duration = max(0, end_ns - start_ns) if count else 0
        info = {
            "version": version, "storage_identifier": "mcap", "relative_file_paths": [name],
            "duration": {"nanoseconds": duration},
            "starting_time": {"nanoseconds_since_epoch": start_ns if count else 0},
            "message_count": count,
            "topics_with_message_count": [
                {"topic_metadata": {"name": c.topic, "type": c.type_name,
                                    "serialization_format": "cdr",
                                    "offered_qos_profiles": self._qos(c.depth, c.latched),
                                    "type_description_hash": typestore(self.distro)
                                    .hash_rihs01(c.type_name)},
                 "message_count": c.count}
                for c in self.channels.values() if c.id is not None
            ],
            "compression_format": "", "compression_mode": "",
            "files": [{"path": name, "starting_time": {"nanoseconds_since_epoch": start_ns},
                       "duration": {"nanoseconds": duration}, "message_count": count}],
            "custom_data": {}, "ros_distro": self.distro.value,
        }  # fmt: skip
        writer.add_metadata("rosbag2", {"serialized_metadata": _yaml(info)})

    def _qos(self, depth: int, latched: bool = False) -> Any:
        """The publisher's offered QoS as rosbag2's metadata holds it: epuck_ros2's
        ``create_publisher(topic, depth)``, i.e. keep last, reliable, volatile; transient
        local where ``latched`` (tf2_ros's static broadcaster)."""
        try:
            from rosbags.interfaces import (
                Qos,
                QosDurability,
                QosHistory,
                QosLiveliness,
                QosReliability,
                QosTime,
            )
            from rosbags.rosbag2.metadata import dump_qos_v8, dump_qos_v9
        except ModuleNotFoundError as exc:  # pragma: no cover - typestore() said it first
            raise missing(exc, "rosbags", "rosbags") from exc
        unset = QosTime(0, 0)  # rmw's "unspecified" duration: the default, infinite
        durability = QosDurability.TRANSIENT_LOCAL if latched else QosDurability.VOLATILE
        qos = Qos(QosHistory.KEEP_LAST, depth, QosReliability.RELIABLE, durability,
                  unset, unset, QosLiveliness.AUTOMATIC, unset, False)  # fmt: skip
        dump = dump_qos_v8 if _BAG_VERSION[self.distro] is None else dump_qos_v9
        return dump([qos])

    def _qos_yaml(self, depth: int, latched: bool) -> str:
        qos = self._qos(depth, latched)
        return qos if isinstance(qos, str) else _yaml(qos)


def _yaml(value: Any) -> str:
    from ruamel.yaml import YAML

    yaml = YAML(typ="safe")
    yaml.default_flow_style = False
    stream = StringIO()
    yaml.dump(value, stream)
    return stream.getvalue().strip()
