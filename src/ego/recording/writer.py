"""``ego run --record run.mcap``: every step of a run, written to MCAP as it happens.

What the step thread does is only to hand over: the exchange's bytes (tapped off the
channel), the step's telemetry sample and, when the camera took a new frame, a copy of
it, onto a queue. A writer thread JSON-encodes, JPEG-encodes and writes them with the
``mcap`` library, so that recording leaves the step timing alone
(``benchmarks/dashboard.py`` measures it). The channels are :mod:`ego.recording.schemas`'.

The file's ``ego`` metadata holds what replaying needs: the firmware and its profile,
the port, and, on the emulator, the world as the dashboard draws it.

``Recorder(path, ros2_distro="jazzy")`` (``--record-format ros2``) writes a ROS 2 bag
instead (:mod:`ego.recording.ros2_bag`): epuck_ros2's topics in CDR, with ego's
exchanges and samples kept as JSON in ``std_msgs/msg/String`` so that it replays alike;
its ``ego`` metadata adds ``format: ros2`` and the distribution.
"""

from __future__ import annotations

import base64
import json
import logging
import queue
import threading
import time
from pathlib import Path
from typing import IO, TYPE_CHECKING, Any

from mcap.writer import Writer

from ego._version import __version__
from ego.camera.encode import encode_jpeg
from ego.core.telemetry import Telemetry, describe_robot, describe_world
from ego.errors import EgoError
from ego.nursery import Nursery
from ego.recording.ros2_bag import FORMAT, Ros2Bag
from ego.recording.schemas import CHANNELS, log_message, pose_message, schema_bytes, stamp
from ego.seam.channel import TappedChannel, as_channel_base

if TYPE_CHECKING:
    import numpy as np

    from ego.core.robot import Robot
    from ego.seam.batch import Batch

__all__ = ["JPEG_QUALITY", "Recorder"]

log = logging.getLogger(__name__)

JPEG_QUALITY = 85
_LEVEL = {"retries": 3, "resyncs": 3, "restarts": 4, "overruns": 3}


class Recorder:
    """Records the first robot it is attached to (``attach`` fits RunOptions.on_robot)."""

    def __init__(self, path: str | Path, ros2_distro: str | None = None) -> None:
        self.path = Path(path)
        if self.path.suffix != ".mcap":
            raise ValueError(f"a recording is an .mcap file, not {str(self.path)!r}")
        # ROS 2 (ego.recording.ros2_bag): checked before the file is made, one line if not.
        self._bag = Ros2Bag(ros2_distro) if ros2_distro is not None else None
        self._channels: dict[str, int] = {}
        self._sequence = 0
        self._span = (0, 0)  # the first and last message times (ns)
        self._file: IO[bytes] = open(self.path, "wb")  # noqa: SIM115 - closed by close()
        self._queue: queue.SimpleQueue[tuple[str, Any, int] | None] = queue.SimpleQueue()
        self._writer: threading.Thread | None = None
        self._robot: Robot | None = None
        self._telemetry: Telemetry | None = None
        self._frames = 0
        self._counters: dict[str, int] = {}
        self.steps = 0
        self._closed = False
        self.failure: BaseException | None = None

    def attach(self, robot: Robot) -> None:
        if self._robot is not None:
            return  # one robot a recording
        self._robot = robot
        self._telemetry = Telemetry(robot)
        info = robot.channel.info
        metadata = {
            "ego_version": __version__,
            "firmware": info.firmware.value,
            "version": info.version,
            "hardware_version": "" if info.hardware_version is None else str(info.hardware_version),
            "selector": "" if info.selector is None else str(info.selector),
            "rev13": {None: "", True: "true", False: "false"}[robot.channel.profile.rev13],
            "robot": json.dumps(describe_robot(robot)),
            "world": json.dumps(describe_world(robot.ground_truth)),
        }
        # A program that exits with its robot open: the recording is finished first.
        self._threads = Nursery("a robot's recorder", join_s=30.0, at_exit=self._finish)
        self._writer = self._threads.start_thread(self._write, metadata, name="ego-recorder")
        robot.tap_channel(self._exchange)
        robot.add_step_listener(self._step)
        # The robot's close ends the writer (after the stop it sends is recorded).
        robot.add_closer(self._finish)

    # -- the step thread: hand over only ------------------------------------------------

    def _exchange(self, batch: Batch, reply: bytes) -> None:
        robot = self._robot
        if robot is None or self._closed:
            return
        self._queue.put(("exchange", (robot.steps + 1, robot.time_s, batch.tx, reply),
                         time.time_ns()))  # fmt: skip

    def _step(self, robot: Robot) -> None:
        assert self._telemetry is not None
        now = time.time_ns()
        sample = self._telemetry.sample()
        self._queue.put(("sample", sample, now))
        camera = robot.open_camera
        if camera is not None and camera.sampling_period and camera.frame_count != self._frames:
            self._frames = camera.frame_count
            image: np.ndarray = camera.image.copy()
            self._queue.put(("image", image, now))
        self.steps += 1

    # -- the writer thread --------------------------------------------------------------

    def _write(self, metadata: dict[str, str]) -> None:
        try:
            writer = Writer(self._file)
            self._start(writer, metadata)
            while (item := self._queue.get()) is not None:
                kind, payload, time_ns = item
                self._span = (self._span[0] or time_ns, time_ns)
                if kind == "exchange":
                    step, t, tx, rx = payload
                    self._put(writer, "/ego/exchange", {"step": step, "t": t, "tx": _b64(tx),
                                                        "rx": _b64(rx)}, time_ns)  # fmt: skip
                elif kind == "image":
                    self._image(writer, payload, time_ns)
                else:
                    self._sample(writer, payload, time_ns)
            if self._bag is not None:
                self._bag.finish(writer, self.path.name, *self._span)
            writer.finish()  # type: ignore[no-untyped-call]
        except (OSError, ValueError, EgoError) as exc:
            self.failure = exc
            log.error("recording to %s failed: %s", self.path, exc)
        finally:
            self._file.close()

    def _start(self, writer: Writer, metadata: dict[str, str]) -> None:
        """The header, schemas and channels: ego's JSON ones, or (ROS 2) the bag's."""
        library = f"ego {__version__}"
        if self._bag is not None:
            writer.start(**self._bag.header(library))
            self._bag.register(writer)
            metadata = {**metadata, "format": FORMAT, "ros2_distro": self._bag.distro.value}
        else:
            writer.start(profile="", library=library)
            schemas: dict[str, int] = {}
            for topic, schema in CHANNELS.items():
                if schema not in schemas:
                    schemas[schema] = writer.register_schema(schema, "jsonschema",
                                                             schema_bytes(schema))  # fmt: skip
                self._channels[topic] = writer.register_channel(topic, "json", schemas[schema])
        writer.add_metadata("ego", metadata)

    def _add(self, writer: Writer, channel: int, data: bytes, time_ns: int) -> None:
        self._sequence += 1
        writer.add_message(channel, time_ns, data, time_ns, self._sequence)

    def _put(self, writer: Writer, topic: str, message: dict[str, Any], time_ns: int) -> None:
        if self._bag is None:
            self._add(writer, self._channels[topic], json.dumps(message).encode(), time_ns)
        elif (found := self._bag.ego(topic, message)) is not None:
            self._add(writer, *found, time_ns)

    def _image(self, writer: Writer, image: np.ndarray, time_ns: int) -> None:
        jpeg = encode_jpeg(image, JPEG_QUALITY)
        if self._bag is not None:
            for channel, data in self._bag.frame(image, jpeg, time_ns):
                self._add(writer, channel, data, time_ns)
            return
        self._put(writer, "/camera/image", {"timestamp": stamp(time_ns), "frame_id": "camera",
                                            "data": _b64(jpeg), "format": "jpeg"}, time_ns)

    def _sample(self, writer: Writer, sample: dict[str, Any], time_ns: int) -> None:
        self._put(writer, "/ego/sensors", sample, time_ns)
        self._put(writer, "/ego/pose/odometry", pose_message(time_ns, sample["odometry"]), time_ns)
        if sample["truth"] is not None:
            self._put(writer, "/ego/pose/truth", pose_message(time_ns, sample["truth"]), time_ns)
        for level, text in self._events(sample):
            self._put(writer, "/ego/log", log_message(time_ns, level, text), time_ns)
        if self._bag is not None:
            for channel, data in self._bag.step(sample, time_ns):
                self._add(writer, channel, data, time_ns)

    def _events(self, sample: dict[str, Any]) -> list[tuple[int, str]]:
        """Link events since the last step: a counter that grew is one log line."""
        counts = {**sample["link"], "overruns": sample["overruns"]}
        events = []
        for name, value in counts.items():
            before = self._counters.get(name, 0)
            if name in _LEVEL and value > before:
                events.append((_LEVEL[name], f"step {sample['step']}: {value - before} "
                               f"{name} (total {value})"))  # fmt: skip
            self._counters[name] = value
        return events

    def close(self) -> None:
        """Finish the file (its summary and index); waits for the writer."""
        self._finish()
        if self.failure is not None:
            raise EgoError(f"recording to {self.path} failed: {self.failure}")

    def _finish(self) -> None:
        """Detach from the robot, let the writer drain the queue and join it; idempotent."""
        if self._closed:
            return
        self._closed = True
        robot = self._robot
        if robot is not None:
            robot.remove_step_hooks(self._step)
            if isinstance(robot.channel, TappedChannel) and robot.channel.tap == self._exchange:
                robot.channel = as_channel_base(robot.channel.inner)  # on, without the tap
        self._queue.put(None)
        if self._writer is not None:
            self._threads.close()
        else:
            self._file.close()


def _b64(data: bytes) -> str:
    return base64.b64encode(data).decode("ascii")
