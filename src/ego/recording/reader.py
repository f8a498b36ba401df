"""Reading an ego recording back: its metadata, and its steps in order.

A :class:`Recording` loads a whole file (a run of minutes is a few MB): the telemetry
samples, the exchanges of each step, and the camera frames, each kept in the order and
with the times they were written.
"""

from __future__ import annotations

import base64
import json
from collections import defaultdict
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from mcap.exceptions import McapError
from mcap.reader import make_reader

from ego.errors import EgoError

__all__ = ["Exchange", "Frame", "Recording", "RecordingError"]


class RecordingError(EgoError, ValueError):
    """A file that is not an ego recording, or one cut short."""


@dataclass(frozen=True, slots=True)
class Exchange:
    step: int
    t: float
    tx: bytes
    rx: bytes


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
        path = Path(path)
        try:
            with open(path, "rb") as f:
                reader = make_reader(f)
                metadata: dict[str, str] = {}
                for record in reader.iter_metadata():
                    if record.name == "ego":
                        metadata = dict(record.metadata)
                if not metadata:
                    raise RecordingError(f"{path}: an MCAP file, but not an ego recording")
                recording = cls(path, metadata, [], [], [], [])
                for _, channel, message in reader.iter_messages(log_time_order=True):
                    recording.topics[channel.topic] = recording.topics.get(channel.topic, 0) + 1
                    recording._take(channel.topic, message.log_time, message.data)
        except (OSError, McapError, ValueError, KeyError) as exc:
            if isinstance(exc, RecordingError):
                raise
            raise RecordingError(f"{path}: not a readable ego recording: {exc}") from exc
        return recording

    def _take(self, topic: str, time_ns: int, data: bytes) -> None:
        if topic == "/ego/sensors":
            self.samples.append(json.loads(data))
            self.sample_times_ns.append(time_ns)
        elif topic == "/ego/exchange":
            m = json.loads(data)
            tx, rx = base64.b64decode(m["tx"]), base64.b64decode(m["rx"])
            self.exchanges.append(Exchange(int(m["step"]), float(m["t"]), tx, rx))
        elif topic == "/camera/image":
            self.frames.append(Frame(time_ns, base64.b64decode(json.loads(data)["data"])))
