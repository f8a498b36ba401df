"""Reading an ego recording back: its metadata, and its steps in order.

A :class:`Recording` loads a whole file (a run of minutes is a few MB): the telemetry
samples, the exchanges of each step, and the camera frames, each kept in the order and
with the times they were written. The file must be a regular file of at most
:data:`MAX_RECORDING_BYTES`, its chunks and messages within the bounds of
:mod:`ego.recording.records`, and each message what its channel's schema says (the
JSON of :mod:`ego.recording.schemas`); anything else is one RecordingError line naming
the file and the reason.
"""

from __future__ import annotations

import base64
import binascii
import json
import math
from collections import defaultdict
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ego.errors import BadFileError, RecordingError
from ego.recording.records import RawMessage, RawRecording, read_records
from ego.recording.schemas import CHANNELS
from ego.seam.files import open_regular

__all__ = ["MAX_RECORDING_BYTES", "Exchange", "Frame", "Recording", "RecordingError"]

#: A recording file's size, at most (a run of minutes is a few MB; it is loaded whole).
MAX_RECORDING_BYTES = 2 << 30


@dataclass(frozen=True, slots=True)
class Exchange:
    step: int
    t: float
    tx: bytes
    rx: bytes
    #: When it was written (its message's log time, ns): when the reply had come.
    time_ns: int = 0


@dataclass(frozen=True, slots=True)
class Frame:
    """A camera frame: the wall time it was written (ns) and its JPEG bytes."""

    time_ns: int
    jpeg: bytes


@dataclass
class Recording:
    path: Path
    metadata: dict[str, str]
    samples: list[dict[str, Any]]
    sample_times_ns: list[int]
    exchanges: list[Exchange]
    frames: list[Frame]
    topics: dict[str, int] = field(default_factory=dict)

    @property
    def robot(self) -> dict[str, Any]:
        return dict(json.loads(self.metadata.get("robot", "{}")))

    @property
    def world(self) -> dict[str, Any] | None:
        world = json.loads(self.metadata.get("world", "null"))
        return dict(world) if world is not None else None

    @property
    def duration_s(self) -> float:
        return float(self.samples[-1]["t"]) if self.samples else 0.0

    def exchanges_by_step(self) -> dict[int, list[Exchange]]:
        by_step: dict[int, list[Exchange]] = defaultdict(list)
        for exchange in self.exchanges:
            by_step[exchange.step].append(exchange)
        return dict(by_step)

    @classmethod
    def open(cls, path: str | Path) -> Recording:
        """The recording at ``path``; RecordingError (one line naming the file) if it is
        not one, is cut short, or is past a bound."""
        path = Path(path)
        try:
            with open_regular(path, MAX_RECORDING_BYTES, "a recording") as file:
                raw = read_records(file, file.size)
        except RecordingError:
            raise
        except BadFileError as exc:  # a FIFO, a device, a file over the bound
            raise RecordingError(str(exc)) from exc
        except (OSError, ValueError) as exc:
            raise RecordingError(f"{path}: not a readable ego recording: {exc}") from exc
        metadata = raw.metadata.get("ego")
        if not metadata:
            raise RecordingError(f"{path}: an MCAP file, but not an ego recording")
        if metadata.get("format") == "ros2":  # ego.recording.ros2_bag: its JSON inside CDR
            from ego.recording.ros2_reading import from_ros2

            raw = from_ros2(raw, str(path), metadata.get("ros2_distro", ""))
        recording = cls(path, metadata, [], [], [], [])
        recording._check(raw)
        for message in raw.messages:
            recording.topics[message.topic] = recording.topics.get(message.topic, 0) + 1
            recording._take(message)
        return recording

    def _check(self, raw: RawRecording) -> None:
        for topic, schema in raw.schemas.items():
            if topic in CHANNELS and schema != CHANNELS[topic]:
                raise RecordingError(f"{self.path}: channel {topic} carries "
                                     f"{schema or 'no schema'!r}, not {CHANNELS[topic]!r}")
        for key, kinds in (("robot", (dict,)), ("world", (dict, type(None)))):
            try:
                value = json.loads(self.metadata.get(key, "{}" if key == "robot" else "null"))
            except (ValueError, RecursionError) as exc:
                raise RecordingError(f"{self.path}: its {key} metadata is not JSON: "
                                     f"{exc}") from exc  # fmt: skip
            if not isinstance(value, kinds):
                raise RecordingError(f"{self.path}: its {key} metadata is a "
                                     f"{type(value).__name__}, not an object")  # fmt: skip

    def _take(self, message: RawMessage) -> None:
        if message.topic not in _TAKEN:
            return
        try:
            m = json.loads(message.data)
        except (ValueError, RecursionError) as exc:
            raise self._bad(message, f"not JSON: {exc}") from exc
        if not isinstance(m, dict):
            raise self._bad(message, f"a JSON {type(m).__name__}, not an object")
        try:
            if message.topic == "/ego/sensors":
                _finite(m, "t")
                self.samples.append(m)
                self.sample_times_ns.append(message.log_time)
            elif message.topic == "/ego/exchange":
                step, t = m.get("step"), _finite(m, "t")
                if not isinstance(step, int) or isinstance(step, bool):
                    raise ValueError(f"its step is {step!r}, not a whole number")
                self.exchanges.append(
                    Exchange(step, t, _b64(m, "tx"), _b64(m, "rx"), message.log_time)
                )
            else:
                self.frames.append(Frame(message.log_time, _b64(m, "data")))
        except ValueError as exc:
            raise self._bad(message, str(exc)) from exc

    def _bad(self, message: RawMessage, reason: str) -> RecordingError:
        number = self.topics.get(message.topic, 0)
        return RecordingError(f"{self.path}: message {number} on {message.topic}: {reason}")


#: The channels a Recording keeps (the poses and the log are for Foxglove).
_TAKEN = frozenset({"/ego/sensors", "/ego/exchange", "/camera/image"})


def _finite(message: dict[str, Any], key: str) -> float:
    value = message.get(key)
    if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
        raise ValueError(f"its {key} is {value!r}, not a finite number")
    return float(value)


def _b64(message: dict[str, Any], key: str) -> bytes:
    value = message.get(key)
    if not isinstance(value, str):
        raise ValueError(f"its {key} is {type(value).__name__}, not base64 text")
    try:
        return base64.b64decode(value, validate=True)
    except binascii.Error as exc:
        raise ValueError(f"its {key} is not base64: {exc}") from exc
