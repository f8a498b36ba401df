"""``ego serve --dashboard``: the robot a PC drives, seen (and stopped) on the robot's side.

``ego serve`` has no Robot: its client's batches pass through. :class:`WatchedChannel`
sits between the server and the robot's channel. It reads each batch and its reply into
a sample (the same keys as :mod:`ego.core.telemetry`'s) and, while the page's stop holds,
turns every wheel command of the client's batches into (0, 0): the PC's controller runs
on, its robot stays put. The page may stop and resume; driving, LEDs and sensors belong
to the controller on the PC, and the page says so.
"""

from __future__ import annotations

import logging
import threading
import time
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

from ego.core.safety import send_stop
from ego.core.telemetry import Sampler, describe_firmware, describe_world, world_pose
from ego.devices.accelerometer import Accelerometer
from ego.devices.base import ArraySensor, Device, Sensor
from ego.devices.encoders import Encoders
from ego.devices.families import make_families
from ego.devices.table import TABLE
from ego.errors import UnsupportedDeviceError
from ego.nursery import Nursery
from ego.seam.batch import Batch, Request
from ego.seam.channel import Channel, ChannelWrapper
from ego.seam.profile import Command
from ego.serial.protocol import encode_batch
from ego.servers.dashboard.control import ControlDesk, Reply
from ego.servers.dashboard.server import DashboardServer

if TYPE_CHECKING:
    from ego.core.ground_truth import GroundTruth

__all__ = ["ServedFeed", "SwarmFeed", "WatchedChannel"]

log = logging.getLogger(__name__)

#: The sensor families a dashboard sample holds (ego.core.telemetry's keys): the device
#: table's sampled families. The served robot's replies are decoded by the families
#: themselves, made for its profile.
_SAMPLED_FAMILIES = tuple(spec.name for spec in TABLE.sampled)


def _reading(family: Device) -> list[float] | None:
    """A family's last sample as the dashboard draws it; None before the first."""
    if isinstance(family, Accelerometer):
        if not family.has_values:
            return None
        return [round(v, 4) for v in family.acceleration_mps2]
    if isinstance(family, (ArraySensor, Encoders)) and family.has_values:
        return [float(v) for v in family.values]
    return None


class WatchedChannel(ChannelWrapper):
    """A channel whose batches a dashboard reads, and whose wheels it may hold stopped.

    Its exchanges, the page's stop and its resume hold the channel's one lock (the
    :class:`~ego.seam.channel.ChannelBase`'s), so a stop never lands inside a batch.
    """

    def __init__(
        self, inner: Channel, on_sample: Any = None, world: GroundTruth | None = None
    ) -> None:
        super().__init__(inner)
        self.world = world
        self.on_sample = on_sample
        self.halted = False
        self._sampler = Sampler(world_pose(world))
        made = make_families(inner.profile)
        self._families = {name: made[name] for name in _SAMPLED_FAMILIES}
        self._readers = {part.command: part for family in self._families.values()
                         for part in family.parts if isinstance(part, Sensor)}  # fmt: skip
        self._speed = [0, 0]
        self._asked = (0, 0)
        self._leds = [0] * 10
        self._battery: int | None = None
        self._steps = 0
        #: The sample of the last batch (None before the first).
        self.last_sample: dict[str, Any] | None = None
        #: The emulated world's true pose after the last batch (None on a real robot).
        self.last_truth: list[float] | None = world_pose(world)
        self._started = time.monotonic()
        self._last = self._started

    def _exchange(self, batch: Batch) -> bytes:
        for request in batch.requests:
            if request.command is Command.SET_SPEED:
                self._asked = (int(request.arguments[0]), int(request.arguments[1]))
        if not self.halted:
            reply = self.inner.exchange(batch)
            self._take(batch, reply)
            return reply
        held = self._stopped(batch)
        reply = self.inner.exchange(held)
        self._take(held, reply)
        return self._as_asked(batch, reply)

    @staticmethod
    def _as_asked(batch: Batch, reply: bytes) -> bytes:
        """The reply to ``batch`` whose speeds the stop held at (0, 0): the ``E`` that
        confirms a speed the client set says that speed, which the server holds for it
        (and applies at :meth:`resume`); otherwise its controller would take the 0, 0 for
        a misread command, ask again and end with a ProtocolError. An ``E`` read on its
        own says the truth: 0, 0."""
        asked: tuple[int, ...] | None = None
        for index, request in enumerate(batch.requests):
            if request.command is Command.SET_SPEED:
                asked = request.arguments
            elif request.command is Command.GET_SPEED and asked is not None:
                reply = batch.with_values(reply, index, asked)
                asked = None
        return reply

    @property
    def battery(self) -> int | None:
        """The battery's last reading in a batch (raw ADC count), None if never read."""
        return self._battery

    def device_families(self) -> list[str]:
        """The sensor families this robot's firmware serves (ego.core.telemetry's names)."""
        profile = self.inner.profile
        return [key for key, family in self._families.items()
                if any(profile.supports(part.command) for part in family.parts
                       if isinstance(part, Sensor))]  # fmt: skip

    def resume(self) -> None:
        """End the stop: the wheels go back to what the client's controller last asked
        (its robot does not know it was stopped, so it would not ask again)."""
        with self._lock:
            self.halted = False
            if self._asked != (0, 0):
                requests = [Request(Command.SET_SPEED, self._asked), Request(Command.GET_SPEED)]
                self.inner.exchange(encode_batch(requests, self.inner.profile))
                self._speed = list(self._asked)

    def _stopped(self, batch: Batch) -> Batch:
        requests = [
            Request(Command.SET_SPEED, (0, 0)) if r.command is Command.SET_SPEED else r
            for r in batch.requests
        ]
        return encode_batch(requests, self.inner.profile)

    def stop(self) -> None:
        """The confirmed stop batch now, between two of the client's batches."""
        with self._lock:
            send_stop(self.inner)
            self._speed = [0, 0]

    def _take(self, batch: Batch, reply: bytes) -> None:
        values = batch.decode(reply) if batch.expects_reply else [()] * len(batch.requests)
        now = time.monotonic()
        now_ms = int((now - self._started) * 1000)
        for request, got in zip(batch.requests, values, strict=True):
            command = request.command
            reader = self._readers.get(command)
            if reader is not None:
                self._decode(reader, request, got, now_ms, now)
            elif command is Command.BATTERY:
                self._battery = int(got[0])
            elif command is Command.SET_SPEED:
                self._speed = [int(v) for v in request.arguments]
            elif command is Command.SET_LED:
                index, value = (int(v) for v in request.arguments)
                if 0 <= index < len(self._leds):
                    self._leds[index] = 1 if value else 0
        step_ms, self._last = (now - self._last) * 1000.0, now
        self._steps += 1
        self.last_truth = world_pose(self.world)
        readings = {key: _reading(family) for key, family in self._families.items()}
        self.last_sample = self._sampler.sample(
            t_s=now - self._started, step=self._steps, step_ms=step_ms, wall_ms=step_ms,
            overruns=None, readings=readings, speed=list(self._speed),
            leds=list(self._leds), battery=self._battery, truth=self.last_truth,
            stats=self.inner.stats,
        )  # fmt: skip
        if self.on_sample is not None:
            self.on_sample(self.last_sample)

    @staticmethod
    def _decode(
        reader: Sensor, request: Request, values: Sequence[float], now_ms: int, now_s: float
    ) -> None:
        """The family takes the reply as a Robot's would; a reply that proves the device
        absent (an accelerometer answering zeros) leaves its reading empty."""
        try:
            reader.apply(request, values, now_ms, now_s)
        except UnsupportedDeviceError as exc:
            log.debug("%s", exc)


def _hello(mode: str, channel: WatchedChannel, name: str) -> dict[str, Any]:
    """What a page is first told of a robot whose batches it reads."""
    profile = channel.info.profile
    families = channel.device_families()
    proximity = profile.reply_values(Command.PROXIMITY) if "proximity" in families else 0
    return {
        "mode": mode,
        "robot": describe_firmware(channel.info, name, remote=False, proximity_count=proximity,
                                   led_count=len(profile.leds) + len(profile.rgb_leds),
                                   families=families),
        "world": describe_world(channel.world),
    }  # fmt: skip


class _StopFeed:
    """A feed whose page may stop and resume the robots of ``channels``, and nothing more:
    their controllers run elsewhere and own their devices."""

    def __init__(self, channels: list[WatchedChannel], hello: dict[str, Any]) -> None:
        self.channels = channels
        self.desk = ControlDesk(can_act=False)
        self.server: DashboardServer | None = None
        self._hello = hello

    def hello(self) -> dict[str, Any]:
        return self._hello

    def state(self, client: object) -> dict[str, Any]:
        return self.desk.state(client)

    def handle(self, client: object, message: object) -> Reply:
        reply = self.desk.handle(client, message)
        for channel in self.channels:
            if self.desk.halted:
                channel.halted = True
            elif channel.halted:
                channel.resume()
        return reply

    def leave(self, client: object) -> None:
        self.desk.leave(client)

    def stop_now(self) -> None:
        for channel in self.channels:
            channel.stop()


class ServedFeed(_StopFeed):
    """The dashboard's view of a served robot: samples from the client's batches, and a
    stop that holds whatever the client sends."""

    def __init__(self, channel: WatchedChannel, port: str) -> None:
        super().__init__([channel], _hello("served", channel, port))
        self.channel = channel
        channel.on_sample = self._on_sample

    def _on_sample(self, sample: dict[str, Any]) -> None:
        if self.server is not None:
            self.server.publish(sample)


class SwarmFeed(_StopFeed):
    """``ego swarm --dashboard``: every robot of a swarm on the map (``swarm``: each one's
    name and true pose), the first one's sensors in detail, and one stop for all. A page
    may pick another robot to detail (``{"type": "pick", "robot": "epuck2"}``): while it
    is picked, its samples come too, under ``details`` by name."""

    def __init__(self, names: list[str], channels: list[WatchedChannel]) -> None:
        super().__init__(channels, {**_hello("swarm", channels[0], names[0]), "robots": names})
        self.names = names
        self._picks: dict[object, str] = {}
        self._closing = threading.Event()
        self._threads = Nursery("the swarm's dashboard feed", join_s=2.0,
                                at_exit=self._closing.set)  # fmt: skip

    def handle(self, client: object, message: object) -> Reply:
        if not (isinstance(message, dict) and message.get("type") == "pick"):
            return super().handle(client, message)
        name = message.get("robot")
        if name not in self.names:
            return Reply({"type": "error", "error": f"robot {name!r} is not one of the "
                          f"swarm's: {', '.join(self.names)}"})  # fmt: skip
        self._picks = {**self._picks, client: str(name)}  # replaced whole: read by _publish
        return Reply()

    def leave(self, client: object) -> None:
        self._picks = {c: n for c, n in self._picks.items() if c != client}
        super().leave(client)

    def _details(self) -> dict[str, Any]:
        """The samples of the robots some page picked (the first one's is the sample)."""
        picked = set(self._picks.values()) - {self.names[0]}
        return {name: channel.last_sample for name, channel in zip(self.names, self.channels,
                strict=True) if name in picked and channel.last_sample is not None}  # fmt: skip

    def start(self) -> SwarmFeed:
        self._threads.start_thread(self._publish, name="ego-swarm-feed")
        return self

    def close(self) -> None:
        self._closing.set()
        self._threads.close()

    def _publish(self) -> None:
        while not self._closing.wait(0.04):
            sample = self.channels[0].last_sample
            if sample is None or self.server is None:
                continue
            swarm = [[name, *(world_pose(c.world) or [0.0, 0.0, 0.0])]
                     for name, c in zip(self.names, self.channels, strict=True)]  # fmt: skip
            self.server.publish({**sample, "swarm": swarm, "details": self._details()})
