"""Webots' ``Emitter`` and ``Receiver``, over Zenoh (ego.zenoh_net.radio).

Webots' e-puck model carries a radio emitter and receiver (channel 1, unlimited range);
the real e-puck has none, so ego gives its controllers one over the network: Zenoh, on
``ego/radio/CHANNEL``. They exist (``getDevice("emitter")``) when eclipse-zenoh is
installed (``pip install ego[zenoh]``) and ``EGO_RADIO`` is not ``none``; otherwise
they are absent, with Webots' warning.

A robot's emitter and receiver share one :class:`RobotRadio`, owned by the Webots
``Robot`` that serves them (ego.controller.robot), opened at first use and closed with the
robot. It uses the robot's Zenoh session when the robot is a Zenoh node
(``zenoh://NAME``), else a session of its own on ``EGO_ZENOH_CONNECT`` /
``EGO_ZENOH_LISTEN`` (ego.zenoh_net.sessions), as the face's environment says.
As in Webots, a packet sent during a step is received at the next one; the queue keeps
a packet until ``nextPacket``, up to a bound (1024 packets, 1 MiB of data:
ego.zenoh_net.radio's BUFFER_PACKETS and BUFFER_BYTES), beyond which arriving packets
are dropped and counted
(``Receiver.dropped_packets``), as Webots' Receiver drops what its ``bufferSize`` cannot
hold.
Signal strength and direction come from the emulated world's true poses (on the
emulator, or a swarm), where the emitter's range is honoured too; on real robots they
are NaN.
"""

from __future__ import annotations

import importlib.util
import math
import os
from collections import deque
from typing import TYPE_CHECKING, Any

from ego.controller.devices import Device
from ego.core.environment import Environment, read_environment
from ego.errors import DeviceError, OutOfRangeError
from ego.seam.validate import MAX_PERIOD_MS, check_int

if TYPE_CHECKING:
    from ego.core.robot import Robot as CoreRobot
    from ego.zenoh_net.radio import Packet, Radio

__all__ = ["RADIO_DEVICES", "Emitter", "Receiver", "RobotRadio", "radio_available"]

#: The names Webots' e-puck gives its radio devices.
RADIO_DEVICES = ("emitter", "receiver")
#: Webots' E-puck PROTO: emitter_channel and receiver_channel default to 1.
DEFAULT_CHANNEL = 1


def radio_available(environment: Environment) -> bool:
    """Whether robots get a radio: eclipse-zenoh is installed and EGO_RADIO is not none."""
    return environment.radio and importlib.util.find_spec("zenoh") is not None


class RobotRadio:
    """One robot's radio, shared by its emitter and receiver: made at first use, closed
    with the robot. Its owner is the Webots Robot that serves both devices."""

    def __init__(self, core: CoreRobot, environment: Environment) -> None:
        self._core = core
        self._environment = environment
        self._radio: Radio | None = None

    def get(self) -> Radio:
        """The radio, opened now if it is not yet."""
        if self._radio is None:
            import zenoh

            from ego.zenoh_net.radio import Radio
            from ego.zenoh_net.sessions import ZenohSettings, open_session

            core = self._core
            # A robot reached over Zenoh (even through a recording's tap) shares its session.
            session = core.channel.session_of(zenoh.Session)
            name = f"{core.port}@{os.uname().nodename}:{os.getpid()}"
            owns = session is None
            if session is None:
                session = open_session(ZenohSettings.from_environment(self._environment))
            radio = Radio(session, name, lambda: _true_pose(core), owns_session=owns)
            self._radio = radio
            core.add_closer(radio.close)
        return self._radio

    @property
    def dropped_total(self) -> int:
        """Packets this robot's radio lost (0 before it opened)."""
        return self._radio.dropped.total if self._radio is not None else 0


def _true_pose(core: CoreRobot) -> list[float] | None:
    truth = core.ground_truth
    pose = truth.pose() if truth is not None else None
    return None if pose is None else [pose.x_m, pose.y_m, pose.theta_rad]


def _check_channel(channel: object) -> int:
    if isinstance(channel, bool) or not isinstance(channel, int) or channel < -1:
        raise OutOfRangeError(f"radio channel {channel!r} must be -1 (broadcast) or 0 and up")
    return channel


class _RadioDevice(Device):
    """What the Emitter and the Receiver share: a channel, 1 by default."""

    CHANNEL_BROADCAST = -1

    def __init__(
        self,
        core: CoreRobot | str,
        name: str = "",
        *,
        strict: bool | None = None,
        radio: RobotRadio | None = None,
    ) -> None:
        if isinstance(core, str):
            return  # made by name (Device.__new__)
        super().__init__(core, name, strict=strict)
        self._channel = DEFAULT_CHANNEL
        #: The robot's radio, shared with its other radio device (None: one of its own).
        self._radio = radio if radio is not None else RobotRadio(core, read_environment())

    def getChannel(self) -> int:
        return self._channel


class Emitter(_RadioDevice):
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
        self._channel = _check_channel(channel)

    def getRange(self) -> float:
        return self._range

    def setRange(self, range: float) -> None:
        value = float(range)
        if not (value == -1 or value >= 0) or math.isnan(value):
            raise OutOfRangeError(f"emitter range {range!r} must be -1 (no limit) or >= 0")
        self._range = value

    def getBufferSize(self) -> int:
        return -1  # Webots' "unlimited"

    channel = property(_RadioDevice.getChannel, setChannel)
    range = property(getRange, setRange)
    buffer_size = property(getBufferSize)


class Receiver(_RadioDevice):
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
        self._channel = _check_channel(channel)
        if self._period:
            self._radio.get().listen(self._channel)

    channel = property(_RadioDevice.getChannel, setChannel)
    queue_length = property(getQueueLength)
    sampling_period = property(getSamplingPeriod)
    data = property(getData)
