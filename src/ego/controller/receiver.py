"""Webots' radio ``Receiver``, over Zenoh (ego.controller.radio says how)."""

from __future__ import annotations

from collections import deque
from typing import TYPE_CHECKING

from ego.controller.radio import RadioDevice, RobotRadio, check_channel
from ego.errors import DeviceError
from ego.seam.validate import MAX_PERIOD_MS, check_int

if TYPE_CHECKING:
    from ego.core.robot import Robot as CoreRobot
    from ego.zenoh_net.radio import Packet

__all__ = ["Receiver"]


class Receiver(RadioDevice):
    """Webots' radio Receiver: a queue of packets, filled at each step while enabled."""

    _node_type = "RECEIVER"

    def __init__(
        self,
        core: CoreRobot | str,
        name: str = "",
        *,
        strict: bool | None = None,
        radio: RobotRadio | None = None,
    ) -> None:
        super().__init__(core, name, strict=strict, radio=radio)
        if isinstance(core, str):
            return  # made by name: the robot's own receiver, its queue kept
        self._period = 0
        self._queue: deque[Packet] = deque()
        self._queued_bytes = 0

    def enable(self, samplingPeriod: int) -> None:
        period = check_int("sampling period", samplingPeriod, 1, MAX_PERIOD_MS, " ms")
        if not self._period:
            self._radio.get().listen(self._channel)
            self._core.add_step_listener(self._step)
        self._period = period

    def disable(self) -> None:
        if self._period:
            self._radio.get().stop_listening()
            self._core.remove_step_hooks(self._step)
        self._period = 0

    def getSamplingPeriod(self) -> int:
        return self._period

    def _step(self, core: CoreRobot) -> None:
        radio = self._radio.get()
        packets = radio.take()
        for index, packet in enumerate(packets):
            if not radio.fits(len(self._queue), self._queued_bytes, len(packet.data)):
                radio.dropped.add("full", "the receiver's queue is full: read it with "
                                  "getData() and nextPacket()", len(packets) - index)  # fmt: skip
                break
            self._queue.append(packet)
            self._queued_bytes += len(packet.data)

    @property
    def dropped_packets(self) -> int:
        """Packets lost (ego's, not Webots'): the buffer full, or malformed; logged too."""
        return self._radio.dropped_total

    def getQueueLength(self) -> int:
        return len(self._queue)

    def nextPacket(self) -> None:
        """Drop the head packet (Webots: an error when the queue is empty)."""
        if not self._queue:
            raise DeviceError("Receiver.nextPacket: the queue is empty")
        self._queued_bytes -= len(self._queue.popleft().data)

    def _head(self) -> Packet:
        if not self._queue:
            raise DeviceError("the receiver's queue is empty: check getQueueLength() first")
        return self._queue[0]

    def getBytes(self) -> bytes:
        return self._head().data

    getData = getBytes

    def getString(self) -> str:
        return self._head().data.decode("utf-8")

    def getDataSize(self) -> int:
        return len(self._head().data)

    def getSignalStrength(self) -> float:
        """1 / distance² from the emitter (Webots'); NaN where the poses are unknown."""
        return self._head().signal_strength

    def getEmitterDirection(self) -> list[float]:
        """The unit vector towards the emitter in this robot's frame; NaNs if unknown."""
        return list(self._head().direction)

    def setChannel(self, channel: int) -> None:
        self._channel = check_channel(channel)
        if self._period:
            self._radio.get().listen(self._channel)

    channel = property(RadioDevice.getChannel, setChannel)
    queue_length = property(getQueueLength)
    sampling_period = property(getSamplingPeriod)
    data = property(getData)
