"""``replay://run.mcap``: a recorded run answering a controller as the robot did.

A bug seen on the real robot is reproduced offline by running the same controller
against its recording: :class:`ReplayChannel` (the seam under ``Robot``) answers the
controller's k-th batch with the reply bytes the robot sent to the k-th batch of the
run, so every value the controller reads is the one it read then, exactly. A controller
that asks for something else than the run's controller did (another sensor, another
order) is told where the two part ways (:class:`ReplayDivergedError`, which ends the
run), and a replay that reaches the end of the recording ends like a link that is gone:
``step`` returns -1. A stop (wheels to 0, LEDs off) that the run did not record is
acknowledged at once: a replay has no wheels to stop.

``replay://run.mcap?speed=4`` paces the controller's steps at four times real time
(0.25, 0.5, 1, 2 or 4; default 1): the controller's own time still advances by each
step's length. Whatever the pace, each reply is judged plausible or not (an encoder's
jump against the time since its last reading) at the time the recorded robot's came, as
it was then: a replay asks again exactly where the recorded run did, never elsewhere.

The camera's frames are in the recording as JPEG for viewing; they are not fed back to
a controller (a JPEG is not the frame the camera gave), so the replayed robot has no
camera.
"""

from __future__ import annotations

import itertools
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any, ClassVar

from ego.core.backend import BackendOptions, Opened
from ego.core.safety import stop_requests
from ego.core.scheduler import StepClock
from ego.errors import (
    FirmwareMismatchError,
    LinkError,
    RecordingError,
    ReplayEndedError,
    UnsupportedDeviceError,
)
from ego.recording.reader import Recording
from ego.seam.batch import Batch
from ego.seam.channel import ChannelBase, FirmwareInfo
from ego.seam.profile import Firmware
from ego.serial.firmware import profile_for
from ego.serial.protocol import parse_batch

__all__ = ["SPEEDS", "ReplayBackend", "ReplayChannel", "ReplayDivergedError", "ReplayEndedError"]

#: Where a recording keeps each batch and its reply (ego.recording.writer).
EXCHANGE_TOPIC = "/ego/exchange"
#: The paces a replay plays at, as multiples of real time (the dashboard's player's too).
SPEEDS = (0.25, 0.5, 1.0, 2.0, 4.0)


class ReplayDivergedError(LinkError):
    """The controller asked what the recorded run never asked: the replay cannot answer.

    Not a lost link (``step`` does not return -1): the run ends with this error, which
    says at which step and what each asked, so that ``ego replay --emulate`` fails.
    """


def _info(recording: Recording) -> FirmwareInfo:
    """The firmware the recorded robot ran, from the file's metadata (RecordingError if the
    metadata cannot say)."""
    try:
        return _firmware_info(recording.metadata)
    except (KeyError, ValueError) as exc:  # a missing key, an unknown firmware, not a number
        reason = f"no {exc}" if isinstance(exc, KeyError) else str(exc)
        raise RecordingError(f"{recording.path}: its metadata cannot say which firmware "
                             f"the robot ran: {reason}") from exc  # fmt: skip


def _firmware_info(metadata: dict[str, str]) -> FirmwareInfo:
    firmware = Firmware(metadata["firmware"])
    selector = int(metadata["selector"]) if metadata.get("selector") else None
    hardware = int(metadata["hardware_version"]) if metadata.get("hardware_version") else None
    rev13 = {"true": True, "false": False}.get(metadata.get("rev13", ""))
    profile = profile_for(firmware, selector, rev13)
    return FirmwareInfo(profile, metadata.get("version", ""), hardware, selector, detected=False)


class ReplayChannel(ChannelBase):
    """The channel of a recorded run (see the module's doc)."""

    def __init__(self, recording: Recording, reply_times_ns: Sequence[int] = ()) -> None:
        super().__init__()
        self.recording = recording
        self._info = _info(recording)
        self._next = 0
        #: When each recorded reply came (wall clock, ns), one an exchange; () if unknown.
        self._reply_times_ns = reply_times_ns
        self._last_reply_s = 0.0

    @property
    def replies_timed(self) -> bool:
        """Whether the recording says when each reply came."""
        return bool(self._reply_times_ns)

    def reply_time(self) -> float:
        """When the recorded robot's reply to the last batch answered came (seconds)."""
        return self._last_reply_s

    @property
    def name(self) -> str:
        return f"replay://{self.recording.path}"

    def _exchange(self, batch: Batch) -> bytes:
        exchanges = self.recording.exchanges
        if self._next >= len(exchanges):
            last = exchanges[-1].step if exchanges else 0
            raise ReplayEndedError(f"{self.name}: the recording ends after step {last}")
        recorded = exchanges[self._next]
        asked = [request.command for request in batch.requests]
        then = [request.command for request in parse_batch(recorded.tx, self.profile).requests]
        if asked != then:
            if list(batch.requests) == stop_requests(self.profile.leds, self.profile.rgb_leds):
                return bytes(batch.reply_size)  # stopped: wheels at (0, 0)
            raise ReplayDivergedError(
                f"{self.name}: at step {recorded.step} the controller asks "
                f"{_letters(asked)}, but the recorded run asked {_letters(then)}: the replay "
                "cannot answer what was never recorded"
            )
        if self._reply_times_ns:
            self._last_reply_s = self._reply_times_ns[self._next] / 1e9
        self._next += 1
        return recorded.rx

    def _ascii_command(self, letter: str, lines: int) -> list[str]:
        if letter.upper() == "V":
            return [f"v,{self._info.version}"][:lines]
        if letter.upper() == "S":
            return []
        raise UnsupportedDeviceError(f"{self.name}: a replay answers no ASCII {letter!r}")

    def _calibrate_proximity(self) -> list[str]:
        raise UnsupportedDeviceError(f"{self.name}: a replay cannot calibrate the sensors")


def _letters(commands: list[Any]) -> str:
    return " ".join(c.letter for c in commands if c.letter) or "nothing"


def _speed(port: str) -> tuple[str, float]:
    """The recording's path in ``port`` and the ``?speed=X`` it asks (1 if none)."""
    path, sep, speed = port.removeprefix("replay://").rpartition("?speed=")
    if not sep:
        return path + speed, 1.0
    try:
        value = float(speed)
    except ValueError:
        value = 0.0
    if value not in SPEEDS:
        raise ValueError(
            f"{port}: replay speed {speed!r} is not one of {', '.join(f'{s:g}' for s in SPEEDS)}"
        )
    return path, value


def paced_clock(speed: float) -> StepClock:
    """A step clock whose seconds last ``1 / speed`` real seconds."""
    return StepClock(clock=lambda: time.perf_counter() * speed,
                     sleep=lambda seconds: time.sleep(seconds / speed))  # fmt: skip


def _reply_times_ns(recording: Recording) -> list[int]:
    """When each recorded exchange's reply came (its message's log time, ns), in order;
    [] when the file's order is not the times' (they cannot be matched one to one)."""
    times = [exchange.time_ns for exchange in recording.exchanges]
    return times if all(a <= b for a, b in itertools.pairwise(times)) else []


class ReplayBackend:
    """``Robot("replay://run.mcap")``: the run recorded in that file, at ``?speed=X``.

    It takes ``firmware`` alone (:class:`~ego.core.backend.BackendOptions`): checked
    against the recorded robot's."""

    options: ClassVar[type[BackendOptions]] = BackendOptions

    def open(self, port: str, options: BackendOptions) -> Opened:
        firmware = options.firmware
        path, speed = _speed(port)
        recording = Recording.open(Path(path))
        channel = ReplayChannel(recording, _reply_times_ns(recording))
        if firmware is not None and channel.info.firmware is not firmware:
            raise FirmwareMismatchError(
                f"{port} recorded a robot with the {channel.info.firmware} firmware, not {firmware}"
            )
        clock = None if speed == 1.0 else paced_clock(speed)
        reply_clock = channel.reply_time if channel.replies_timed else None
        return Opened(channel, pacer=clock, reply_clock=reply_clock)
