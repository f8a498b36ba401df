"""``replay://run.mcap``: a recorded run answering a controller as the robot did.

A bug seen on the real robot is reproduced offline by running the same controller
against its recording: :class:`ReplayChannel` (the seam under ``Robot``) answers the
controller's k-th batch with the reply bytes the robot sent to the k-th batch of the
run, so every value the controller reads is the one it read then, exactly. A controller
that asks for something else than the run's controller did (another sensor, another
order) is told where the two part ways, and a replay that reaches the end of the
recording ends like a link that is gone: ``step`` returns -1.

The camera's frames are in the recording as JPEG for viewing; they are not fed back to
a controller (a JPEG is not the frame the camera gave), so the replayed robot has no
camera.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from ego.backends import Opened
from ego.errors import LinkLostError, RecordingError, UnsupportedDeviceError
from ego.recording.reader import Recording
from ego.serial.firmware import FirmwareInfo, gctronic_profile
from ego.serial.link import LinkStats
from ego.serial.protocol import PROFILES, Batch, Firmware, Profile, parse_batch

__all__ = ["ReplayBackend", "ReplayChannel", "ReplayEndedError"]


class ReplayEndedError(LinkLostError):
    """The recording has no more steps, or the controller asked what it never recorded."""

    def __init__(self, message: str, *, expected: bool = False) -> None:
        super().__init__(message)
        #: True at the recording's end: the run is over, as it was then, not broken.
        self.expected = expected


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
    profile = (
        gctronic_profile(selector, rev13)
        if firmware is Firmware.GCTRONIC
        else PROFILES[Firmware.WEBOTS]
    )
    return FirmwareInfo(profile, metadata.get("version", ""), hardware, selector, detected=False)


class ReplayChannel:
    """The channel of a recorded run (see the module's doc)."""

    def __init__(self, recording: Recording) -> None:
        self.recording = recording
        self._info = _info(recording)
        self._stats = LinkStats()
        self._next = 0

    @property
    def name(self) -> str:
        return f"replay://{self.recording.path}"

    @property
    def info(self) -> FirmwareInfo:
        return self._info

    @property
    def stats(self) -> LinkStats:
        return self._stats

    @property
    def profile(self) -> Profile:
        return self._info.profile

    def exchange(self, batch: Batch) -> bytes:
        exchanges = self.recording.exchanges
        if self._next >= len(exchanges):
            last = exchanges[-1].step if exchanges else 0
            raise ReplayEndedError(f"{self.name}: the recording ends after step {last}",
                                   expected=True)  # fmt: skip
        recorded = exchanges[self._next]
        asked = [request.command for request in batch.requests]
        then = [request.command for request in parse_batch(recorded.tx, self.profile).requests]
        if asked != then:
            raise ReplayEndedError(
                f"{self.name}: at step {recorded.step} the controller asks "
                f"{_letters(asked)}, but the recorded run asked {_letters(then)}: the replay "
                "cannot answer what was never recorded"
            )
        self._next += 1
        self._stats.batches += 1
        self._stats.bytes_sent += len(batch.tx)
        self._stats.bytes_received += len(recorded.rx)
        return recorded.rx

    def ascii_command(self, letter: str, lines: int = 1) -> list[str]:
        if letter.upper() == "V":
            return [f"v,{self._info.version}"][:lines]
        if letter.upper() == "S":
            return []
        raise UnsupportedDeviceError(f"{self.name}: a replay answers no ASCII {letter!r}")

    def calibrate_proximity(self) -> list[str]:
        raise UnsupportedDeviceError(f"{self.name}: a replay cannot calibrate the sensors")

    def waiting_until(self, deadline_s: float) -> None:
        pass

    def close(self) -> None:
        pass


def _letters(commands: list[Any]) -> str:
    return " ".join(c.letter for c in commands if c.letter) or "nothing"


class ReplayBackend:
    """``Robot("replay://run.mcap")``: the run recorded in that file (no options)."""

    def open(self, port: str, *, firmware: Firmware | None) -> Opened:
        path = Path(port.removeprefix("replay://"))
        recording = Recording.open(path)
        channel = ReplayChannel(recording)
        if firmware is not None and channel.info.firmware is not firmware:
            raise UnsupportedDeviceError(
                f"{port} recorded a robot with the {channel.info.firmware} firmware, not {firmware}"
            )
        return Opened(channel)
