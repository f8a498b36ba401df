"""``ego run --record run.mcap``: every step of a run, written to MCAP as it happens.

What the step thread does is only to hand over: the exchange's bytes (tapped off the
channel), the step's telemetry sample and, when the camera took a new frame, a copy of
it, onto a queue. A writer thread JSON-encodes, JPEG-encodes and writes them with the
``mcap`` library, so that recording leaves the step timing alone
(``benchmarks/dashboard.py`` measures it). The channels are :mod:`ego.recording.schemas`'.

The file's ``ego`` metadata holds what replaying needs: the firmware and its profile,
the port, and, on the emulator, the world as the dashboard draws it.
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
from ego.core.channel import TappedChannel, as_channel_base
from ego.core.telemetry import Telemetry, describe_robot, describe_world
from ego.errors import EgoError
from ego.recording.schemas import CHANNELS, log_message, pose_message, schema_bytes, stamp

if TYPE_CHECKING:
    import numpy as np

    from ego.core.robot import Robot
    from ego.serial.protocol import Batch

__all__ = ["JPEG_QUALITY", "Recorder"]

log = logging.getLogger(__name__)

JPEG_QUALITY = 85
_LEVEL = {"retries": 3, "resyncs": 3, "restarts": 4, "overruns": 3}


class Recorder:
    """Records the first robot it is attached to (``attach`` fits RunOptions.on_robot)."""

    def __init__(self, path: str | Path) -> None:
        self.path = Path(path)
        if self.path.suffix != ".mcap":
            raise ValueError(f"a recording is an .mcap file, not {str(self.path)!r}")
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
        self._writer = threading.Thread(
            target=self._write, args=(metadata,), name="ego-recorder", daemon=True
        )
        self._writer.start()
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
            writer.start(profile="", library=f"ego {__version__}")
            schemas: dict[str, int] = {}
            channels: dict[str, int] = {}
            for topic, schema in CHANNELS.items():
                if schema not in schemas:
                    schemas[schema] = writer.register_schema(schema, "jsonschema",
                                                             schema_bytes(schema))  # fmt: skip
                channels[topic] = writer.register_channel(topic, "json", schemas[schema])
            writer.add_metadata("ego", metadata)
            sequence = 0

            def put(topic: str, message: dict[str, Any], time_ns: int) -> None:
                nonlocal sequence
                sequence += 1
                writer.add_message(channels[topic], time_ns, json.dumps(message).encode(),
                                   time_ns, sequence)  # fmt: skip

            while (item := self._queue.get()) is not None:
                kind, payload, time_ns = item
                if kind == "exchange":
                    step, t, tx, rx = payload
                    put("/ego/exchange", {"step": step, "t": t, "tx": _b64(tx), "rx": _b64(rx)},
                        time_ns)  # fmt: skip
                elif kind == "image":
                    put("/camera/image", {"timestamp": stamp(time_ns), "frame_id": "camera",
                                          "data": _b64(encode_jpeg(payload, JPEG_QUALITY)),
                                          "format": "jpeg"}, time_ns)  # fmt: skip
                else:
                    put("/ego/sensors", payload, time_ns)
                    put("/ego/pose/odometry", pose_message(time_ns, payload["odometry"]), time_ns)
                    if payload["truth"] is not None:
                        put("/ego/pose/truth", pose_message(time_ns, payload["truth"]), time_ns)
                    for level, text in self._events(payload):
                        put("/ego/log", log_message(time_ns, level, text), time_ns)
            writer.finish()  # type: ignore[no-untyped-call]
        except (OSError, ValueError, EgoError) as exc:
            self.failure = exc
            log.error("recording to %s failed: %s", self.path, exc)
        finally:
            self._file.close()

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
            self._writer.join(30)
        else:
            self._file.close()


def _b64(data: bytes) -> str:
    return base64.b64encode(data).decode("ascii")
