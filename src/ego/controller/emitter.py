"""Webots' radio ``Emitter``, over Zenoh (ego.controller.radio says how)."""

from __future__ import annotations

import math
from typing import Any

from ego.controller.radio import RadioDevice, check_channel
from ego.errors import DeviceError, OutOfRangeError

__all__ = ["Emitter"]


class Emitter(RadioDevice):
    """Webots' radio Emitter: ``send(data)`` puts a packet on its channel."""

    _node_type = "EMITTER"
    _range = -1.0

    def send(self, message: bytes | str | Any) -> int:
        """Send ``message`` (bytes, or text as UTF-8); 1, as Webots answers when sent."""
        if isinstance(message, str):
            data = message.encode("utf-8")
        elif isinstance(message, bytes | bytearray | memoryview):
            data = bytes(message)
        else:
            raise DeviceError(f"Emitter.send takes bytes or a str, not {type(message).__name__}")
        self._radio.get().send(self._channel, data, self._range)
        return 1

    def setChannel(self, channel: int) -> None:
        self._channel = check_channel(channel)

    def getRange(self) -> float:
        return self._range

    def setRange(self, range: float) -> None:
        value = float(range)
        if not (value == -1 or value >= 0) or math.isnan(value):
            raise OutOfRangeError(f"emitter range {range!r} must be -1 (no limit) or >= 0")
        self._range = value

    def getBufferSize(self) -> int:
        return -1  # Webots' "unlimited"

    channel = property(RadioDevice.getChannel, setChannel)
    range = property(getRange, setRange)
    buffer_size = property(getBufferSize)
