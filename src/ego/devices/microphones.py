"""The three microphones: amplitudes (wire command u) and the raw sample buffer (U)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

from ego.devices.base import ArraySensor, Verdict, out_of_range
from ego.devices.table import TABLE, Series
from ego.errors import DeviceError
from ego.seam.batch import Request
from ego.seam.profile import Command, Profile
from ego.seam.validate import MAX_PERIOD_MS, check_int

if TYPE_CHECKING:  # numpy is imported when a buffer first arrives (import ego stays light)
    import numpy as np
    import numpy.typing as npt

__all__ = ["MIC_RATE_HZ", "MIC_SAMPLES", "Microphones"]

MIC_RATE_HZ = 16384
MIC_SAMPLES = 100


@TABLE.declare(
    "microphones",
    webots_rank=7,
    series=Series("microphones", "amplitude, ADC counts", ("mic0", "mic1", "mic2", "mic3")),
)
class Microphones(ArraySensor):
    """Amplitude (max - min of the last 100 samples, 0..4095) of mic0..mic2, and their samples.

    The raw buffer (``U``) is 600 bytes a fetch, 14 ms of line time at 230400 baud: it has
    its own period so that amplitudes can be sampled faster.

    >>> robot.microphones.enable(100)                    # doctest: +SKIP
    >>> robot.microphones.enable_buffer(500)
    >>> robot.step(100); samples = robot.microphones.buffer   # (3, 100) uint16, oldest first

    The buffer is not a snapshot (docs/protocol.md, "U"): the dsPIC sends it straight from
    the array its ADC interrupt keeps writing, so samples near the write position may be
    newer than the index byte says.
    """

    family = "microphones"
    command = Command.MIC_AMPLITUDE

    def __init__(self, profile: Profile) -> None:
        super().__init__(profile)
        self._buffer_period: int | None = None
        self._buffer_fetch_ms: int | None = None
        self._buffer: npt.NDArray[np.uint16] | None = None

    @property
    def member_names(self) -> tuple[str, ...]:
        # The e-puck2 has four (right, left, back, front), read with -0x0C.
        return self.names[: self.profile.reply_values(self.current_command()) or 3]

    def current_command(self) -> Command:
        """``u`` on an e-puck1; the e-puck2's -0x0C, which also has its fourth."""
        four = Command.MICROPHONES_4
        return four if self.profile.supports(four) else Command.MIC_AMPLITUDE

    def command_for_enable(self) -> Command:
        return self.current_command()

    def enable_buffer(self, period_ms: int) -> None:
        """Fetch the raw 3 x 100 samples every ``period_ms``."""
        self.require(Command.MIC_BUFFER)
        self._buffer_period = check_int("sampling period", period_ms, 1, MAX_PERIOD_MS, " ms")

    def disable_buffer(self) -> None:
        self._buffer_period = None
        self._buffer_fetch_ms = None

    def plan(self, now_ms: int) -> list[Request]:
        reqs = super().plan(now_ms)
        period = self._buffer_period
        if period is not None and (
            self._buffer_fetch_ms is None or now_ms - self._buffer_fetch_ms >= period
        ):
            reqs.append(Request(Command.MIC_BUFFER))
        return reqs

    def validate(self, request: Request, values: Sequence[float], now_s: float) -> Verdict:
        if request.command is Command.MIC_BUFFER:
            return Verdict(
                out_of_range("microphone buffer index", values[300:], 0, MIC_SAMPLES - 1)
            )
        return super().validate(request, values, now_s)

    def apply(self, request: Request, values: Sequence[float], now_ms: int, now_s: float) -> None:
        if request.command is Command.MIC_BUFFER:
            import numpy as np

            self._buffer_fetch_ms = now_ms
            # Unsigned ADC counts around mid-scale (docs/protocol.md, "U"); the wire
            # format is signed, the values never reach 0x8000.
            samples = np.asarray(values[:300], dtype=np.int64).astype(np.uint16)
            samples = samples.reshape(3, MIC_SAMPLES)
            # The index byte is the slot the ADC writes next, that is the oldest sample
            # of the circular buffer: oldest first means starting there.
            self._buffer = np.roll(samples, -int(values[300]), axis=1)
        else:
            super().apply(request, values, now_ms, now_s)

    @property
    def buffer(self) -> npt.NDArray[np.uint16]:
        """(3, 100) ADC samples of mic0..mic2 at 16384 Hz (mid-scale is silence), oldest first."""
        if self._buffer is None:
            raise DeviceError(
                "the microphone buffer has not been fetched: enable_buffer() and step()"
            )
        return self._buffer

    def reset(self) -> None:
        super().reset()
        self._buffer_fetch_ms = None
