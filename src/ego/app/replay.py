"""``ego replay run.mcap``: a recorded run played back into the dashboard.

A :class:`ReplayFeed` is a dashboard :class:`~ego.servers.dashboard.server.Feed` whose samples
and camera frames come from a :class:`~ego.recording.reader.Recording`, paced by the
samples' controller time at the chosen speed, with pause and seek from any page (there
is no robot to harm: every page may steer the playback, none may act on a robot).

The playing thread is the feed's, in a :class:`~ego.nursery.Nursery`: :meth:`ReplayFeed.close`
ends and joins it (a thread still running 5 s later is a ThreadLeakError), and a program
that exits with the feed still open has it closed before Python waits for its threads.
"""

from __future__ import annotations

import bisect
import threading
import time
from typing import Any

from ego.backends.replay import SPEEDS
from ego.devices.table import TABLE
from ego.errors import RecordingError
from ego.nursery import Nursery
from ego.recording.reader import Recording
from ego.servers.dashboard.control import Reply
from ego.servers.dashboard.server import DashboardServer

__all__ = ["SPEEDS", "ReplayFeed"]


class ReplayFeed:
    def __init__(self, recording: Recording, speed: float = 1.0, playing: bool = True) -> None:
        if not recording.samples:
            raise RecordingError(f"{recording.path}: the recording holds no step")
        if speed not in SPEEDS:
            raise ValueError(f"replay speed {speed} is not one of {', '.join(map(str, SPEEDS))}")
        self.recording = recording
        self.speed = speed
        self.playing = playing
        self.server: DashboardServer | None = None
        self._times = [float(s["t"]) for s in recording.samples]
        self._frame_times = [f.time_ns for f in recording.frames]
        self._index = 0
        self._lock = threading.Lock()
        self._changed = threading.Event()
        self._closed = threading.Event()
        self._nursery = Nursery("ego-replay", at_exit=self.close)

    # -- the Feed -----------------------------------------------------------------------

    def hello(self) -> dict[str, Any]:
        # A recording made before the page was told the series draws with today's table's.
        robot = {"series": TABLE.describe_series(), **self.recording.robot}
        return {"mode": "replay", "robot": robot, "world": self.recording.world}

    def state(self, client: object) -> dict[str, Any]:
        with self._lock:
            t = self._times[self._index]
        duration = self._times[-1]
        return {
            "type": "state", "role": "view", "held": False, "halted": False, "keyboard": False,
            "replay": {"t": t, "duration": duration, "position": t / duration if duration else 0.0,
                       "playing": self.playing, "speed": self.speed},
        }  # fmt: skip

    def handle(self, client: object, message: object) -> Reply:
        if not isinstance(message, dict) or message.get("type") != "replay":
            return Reply({"type": "error", "error": "a replay has no robot to act on"})
        action = message.get("action")
        with self._lock:
            if action in ("play", "pause"):
                self.playing = action == "play"
            elif action == "seek" and isinstance(message.get("position"), int | float):
                target = max(0.0, min(1.0, float(message["position"]))) * self._times[-1]
                self._index = min(bisect.bisect_left(self._times, target), len(self._times) - 1)
            elif action == "speed" and message.get("speed") in SPEEDS:
                self.speed = float(message["speed"])
            else:
                return Reply({"type": "error", "error": f"replay command {message!r} is not "
                              "play, pause, seek with a position 0..1, or a speed among "
                              f"{', '.join(map(str, SPEEDS))}"})  # fmt: skip
        self._changed.set()
        return Reply()

    def leave(self, client: object) -> None:
        pass

    def stop_now(self) -> None:
        pass

    # -- playing ------------------------------------------------------------------------

    def start(self) -> None:
        self._nursery.start_thread(self._play, name="ego-replay")

    def close(self) -> None:
        """End the playing thread and join it (ThreadLeakError if it is still running
        5 s later); idempotent."""
        self._closed.set()
        self._changed.set()
        self._nursery.close()

    def finished(self) -> bool:
        return self._index >= len(self._times) - 1 and not self.playing

    def _play(self) -> None:
        anchor_wall, anchor_t = time.monotonic(), self._times[0]
        shown = -1
        while not self._closed.is_set():
            with self._lock:
                if self._changed.is_set():  # seek, speed or pause: re-anchor the clock
                    self._changed.clear()
                    anchor_wall, anchor_t = time.monotonic(), self._times[self._index]
                if self.playing:
                    t = anchor_t + (time.monotonic() - anchor_wall) * self.speed
                    self._index = min(bisect.bisect_right(self._times, t) - 1,
                                      len(self._times) - 1)  # fmt: skip
                    self._index = max(self._index, 0)
                    if self._index == len(self._times) - 1:
                        self.playing = False
                index = self._index
            if index != shown:
                self._show(index)
                shown = index
            self._changed.wait(0.02)

    def _show(self, index: int) -> None:
        server = self.server
        if server is None:
            return
        server.publish(self.recording.samples[index], force=True)
        at = bisect.bisect_right(self._frame_times, self.recording.sample_times_ns[index]) - 1
        if at >= 0 and server.wants_image():
            server.publish_image(self.recording.frames[at].jpeg)
