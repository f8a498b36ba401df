"""The seam under :class:`~ego.core.robot.Robot`: one batch per step, ASCII commands, a close.

A ``Robot`` talks to its dsPIC through a :class:`Channel` and through nothing else. The
serial :class:`~ego.serial.link.Link` is one: it speaks the bytes of
docs/protocol.md over a byte transport (a serial port, a pty, a pyserial URL). The
network client :class:`~ego.backends.remote.channel.RemoteChannel` is another: it carries the
same batches, as lists of requests, to ``ego serve``, which runs them on its own link
and returns their reply bytes, or the ego error they met, with its fields. Backends
(:mod:`ego.backends`) open a channel for a port's scheme; ``tests/contract`` holds the
suite every channel passes.

Every channel derives from :class:`ChannelBase`, whose public methods do what all of them
must do once (python-can's ``BusABC.recv`` calling ``_recv_internal``): they hold the
channel's lock, so two threads may share a channel with no lock of their own; they refuse
a closed channel; ``exchange`` checks the reply's length and counts the batch in
``stats``. A subclass writes only ``_exchange``, ``_ascii_command``,
``_calibrate_proximity`` and ``_close``. A channel that wraps another (a recording's tap,
a dashboard's watch) derives from :class:`ChannelWrapper`: it forwards what it does not
change, ``stats`` and :meth:`ChannelBase.session_of` included, and counts nothing twice.
"""

from __future__ import annotations

import abc
import threading
import time
from collections import Counter
from collections.abc import Callable
from contextlib import AbstractContextManager
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Protocol, TypeVar, runtime_checkable

from ego.errors import ExtraBytesError, LinkLostError, ShortReplyError

if TYPE_CHECKING:
    from ego.seam.batch import Batch
    from ego.seam.profile import Firmware, Profile

__all__ = [
    "Channel",
    "ChannelBase",
    "ChannelWrapper",
    "FirmwareInfo",
    "LinkStats",
    "TappedChannel",
    "as_channel_base",
    "reconnect_within",
]

T = TypeVar("T")


@dataclass(frozen=True, slots=True)
class FirmwareInfo:
    """The profile in use and what the firmware said of itself."""

    profile: Profile
    version: str = ""
    #: The ``HW version`` EEPROM word (0xFFFF when never written), None if not said.
    hardware_version: int | None = None
    selector: int | None = None
    #: False when the profile was given explicitly rather than probed.
    detected: bool = True

    @property
    def firmware(self) -> Firmware:
        return self.profile.firmware


@dataclass(slots=True)
class LinkStats:
    """Counters of what a channel did and what went wrong, for logs and benchmarks.

    ``batches`` and the byte counts are those of the exchanges that completed, counted
    once each by :meth:`ChannelBase.exchange`; the rest is the channel's own (a serial
    link's retries and resynchronisations, a network channel's reconnections)."""

    batches: int = 0
    bytes_sent: int = 0
    bytes_received: int = 0
    retries: int = 0
    resyncs: int = 0
    restarts: int = 0
    reconnects: int = 0
    faults: Counter[str] = field(default_factory=Counter)


@runtime_checkable
class Channel(Protocol):
    """What a Robot needs of the way to its dsPIC."""

    @property
    def name(self) -> str:
        """Where the channel goes ("/dev/ttyS0", "tcp://robot:4242"), for messages."""
        ...

    @property
    def info(self) -> FirmwareInfo:
        """What answers at the other end: the firmware, its profile and version."""
        ...

    @property
    def stats(self) -> LinkStats:
        """Batches, retries, faults: what the channel met (Robot counts implausible replies)."""
        ...

    @property
    def profile(self) -> Profile:
        """The wire format of the firmware at the other end (``info.profile``)."""
        ...

    def exchange(self, batch: Batch) -> bytes:
        """Run one batch; exactly its ``reply_size`` reply bytes (b'' when it asks none).

        Raises RobotResetError when the robot restarted (``info`` is then up to date and
        the owner re-applies its state), LinkLostError when the way is gone for good,
        and the link's other errors after its own bounded retries.
        """
        ...

    def ascii_command(self, letter: str, lines: int = 1) -> list[str]:
        """One ASCII command (``V``, ``C``, ``S``...); up to ``lines`` reply lines."""
        ...

    def calibrate_proximity(self) -> list[str]:
        """The ASCII ``K``, waiting out the calibration; its reply lines."""
        ...

    def waiting_until(self, deadline_s: float) -> None:
        """The owner waits out a step until ``deadline_s`` (time.monotonic()); a network
        channel keeps its session alive that long and no longer."""
        ...

    def close(self) -> None:
        """Release the way to the robot; idempotent (the owner stops the robot first)."""
        ...


def reconnect_within(
    name: str,
    timeout_s: float,
    attempt: Callable[[], None],
    not_back_yet: tuple[type[Exception], ...],
    cause: LinkLostError,
) -> None:
    """Call ``attempt`` until it succeeds, every 50 ms, for at most ``timeout_s``; then
    LinkLostError. What a channel does when its way to the robot vanished (a re-plugged
    USB port, a restarted server): ``not_back_yet`` are the errors that mean "try again"."""
    deadline = time.monotonic() + timeout_s
    while True:
        try:
            attempt()
            return
        except not_back_yet as exc:
            if time.monotonic() > deadline:
                raise LinkLostError(
                    f"{name}: lost, and not back within {timeout_s} s: {exc}"
                ) from cause
            time.sleep(0.05)


class ChannelBase(abc.ABC):
    """What every channel does once (see the module's doc); subclasses write the ``_`` methods.

    A subclass sets ``_info`` before its first exchange and says its ``name``.
    """

    #: Whether :meth:`exchange` counts the batch in ``stats`` (a wrapper's inner channel did).
    _counts = True

    def __init__(self) -> None:
        self._lock = threading.RLock()
        self._stats = LinkStats()
        self._closed = False

    @property
    @abc.abstractmethod
    def name(self) -> str:
        """Where the channel goes ("/dev/ttyS0", "tcp://robot:4242"), for messages."""

    @property
    def info(self) -> FirmwareInfo:
        return self._info

    @property
    def stats(self) -> LinkStats:
        return self._stats

    @property
    def profile(self) -> Profile:
        """The wire formats of the firmware at the other end (``info.profile``)."""
        return self.info.profile

    @property
    def closed(self) -> bool:
        return self._closed

    @property
    def lock(self) -> AbstractContextManager[bool]:
        """The channel's own lock (re-entrant), which each of its calls takes: held by a
        caller that must keep other threads off the channel across several calls (a
        Robot's step and its recovery, a server's "is this session still live?" check
        and its batch)."""
        return self._lock

    def exchange(self, batch: Batch) -> bytes:
        """Run one batch (see :class:`Channel`); exactly its ``reply_size`` bytes, or
        ShortReplyError naming both sizes."""
        with self._lock:
            self._check_open()
            reply = self._exchange(batch)
            if len(reply) != batch.reply_size:
                error = ShortReplyError if len(reply) < batch.reply_size else ExtraBytesError
                if self._counts:
                    self._stats.faults[error.__name__] += 1
                raise error(
                    f"{self.name}: {len(reply)} reply bytes, the batch asks for {batch.reply_size}"
                )
            if self._counts:
                self._stats.batches += 1
                self._stats.bytes_sent += len(batch.tx)
                self._stats.bytes_received += len(reply)
            return reply

    def ascii_command(self, letter: str, lines: int = 1) -> list[str]:
        """One ASCII command (``V``, ``C``, ``S``...); up to ``lines`` reply lines."""
        with self._lock:
            self._check_open()
            return self._ascii_command(letter, lines)

    def calibrate_proximity(self) -> list[str]:
        """The ASCII ``K``, waiting out the calibration; its reply lines."""
        with self._lock:
            self._check_open()
            return self._calibrate_proximity()

    def waiting_until(self, deadline_s: float) -> None:
        """The owner waits out a step until ``deadline_s``; nothing to do by default."""
        return

    def close(self) -> None:
        """Release the way to the robot, once; later calls do nothing, later exchanges
        raise LinkLostError."""
        with self._lock:
            if self._closed:
                return
            self._closed = True
            self._close()

    def session_of(self, kind: type[T]) -> T | None:
        """The network session of type ``kind`` this channel runs on (a Zenoh session, so
        that a robot's radio shares it rather than open a second one); None if none.
        Wrappers forward the question to the channel they wrap."""
        return None

    def _check_open(self) -> None:
        if self._closed:
            raise LinkLostError(f"{self.name}: the channel is closed")

    # -- what a subclass writes ---------------------------------------------------------------

    _info: FirmwareInfo

    @abc.abstractmethod
    def _exchange(self, batch: Batch) -> bytes:
        """Run one batch (under the lock, the channel open); its reply bytes."""

    @abc.abstractmethod
    def _ascii_command(self, letter: str, lines: int) -> list[str]:
        """One ASCII command (under the lock, the channel open); its reply lines."""

    @abc.abstractmethod
    def _calibrate_proximity(self) -> list[str]:
        """The ASCII ``K`` (under the lock, the channel open); its reply lines."""

    def _close(self) -> None:
        """Release what the channel holds (called once, under the lock); nothing by default."""
        return


class ChannelWrapper(ChannelBase):
    """A channel around another (``inner``): it forwards what it does not change, and its
    ``stats`` are the inner channel's, counted there once."""

    _counts = False

    def __init__(self, inner: Channel) -> None:
        super().__init__()
        self.inner = inner

    @property
    def name(self) -> str:
        return self.inner.name

    @property
    def info(self) -> FirmwareInfo:
        return self.inner.info

    @property
    def stats(self) -> LinkStats:
        return self.inner.stats

    def session_of(self, kind: type[T]) -> T | None:
        inner = self.inner
        return inner.session_of(kind) if isinstance(inner, ChannelBase) else None

    def _exchange(self, batch: Batch) -> bytes:
        return self.inner.exchange(batch)

    def _ascii_command(self, letter: str, lines: int) -> list[str]:
        return self.inner.ascii_command(letter, lines)

    def _calibrate_proximity(self) -> list[str]:
        return self.inner.calibrate_proximity()

    def waiting_until(self, deadline_s: float) -> None:
        self.inner.waiting_until(deadline_s)

    def _close(self) -> None:
        self.inner.close()


def as_channel_base(channel: Channel) -> ChannelBase:
    """``channel`` itself if it derives from ChannelBase, else wrapped in one (a channel a
    user wrote to the Protocol alone): what a Robot or a server holds is always locked."""
    return channel if isinstance(channel, ChannelBase) else ChannelWrapper(channel)


class TappedChannel(ChannelWrapper):
    """A channel that also hands every completed exchange (the batch and its reply) to
    ``tap``: what a recording keeps. Everything else goes to ``inner`` unchanged."""

    def __init__(self, inner: Channel, tap: Callable[[Batch, bytes], None]) -> None:
        super().__init__(inner)
        self.tap = tap

    def _exchange(self, batch: Batch) -> bytes:
        reply = self.inner.exchange(batch)
        self.tap(batch, reply)
        return reply
