"""The seam under :class:`~ego.core.robot.Robot`: one batch per step, ASCII commands, a close.

A ``Robot`` talks to its dsPIC through a :class:`Channel` and through nothing else. The
serial :class:`~ego.serial.link.Link` is one: it speaks the bytes of
docs/protocol.md over a byte transport (a serial port, a pty, a pyserial URL). The
network client :class:`~ego.backends.remote.channel.RemoteChannel` is another: it carries the
same batches, as lists of requests, to ``ego serve``, which runs them on its own link
and returns their reply bytes, or the ego error they met, with its fields. Backends
(:mod:`ego.backends`) open a channel for a port's scheme; ``tests/contract`` holds the
suite every channel passes.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import TYPE_CHECKING, Protocol, runtime_checkable

from ego.errors import LinkLostError

if TYPE_CHECKING:
    from ego.serial.firmware import FirmwareInfo
    from ego.serial.link import LinkStats
    from ego.serial.protocol import Batch, Profile

__all__ = ["Channel", "TappedChannel", "reconnect_within"]


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


class TappedChannel:
    """A channel that also hands every completed exchange (the batch and its reply) to
    ``tap``: what a recording keeps. Everything else goes to ``inner`` unchanged."""

    def __init__(self, inner: Channel, tap: Callable[[Batch, bytes], None]) -> None:
        self.inner = inner
        self.tap = tap

    @property
    def name(self) -> str:
        return self.inner.name

    @property
    def info(self) -> FirmwareInfo:
        return self.inner.info

    @property
    def stats(self) -> LinkStats:
        return self.inner.stats

    @property
    def profile(self) -> Profile:
        return self.inner.profile

    def exchange(self, batch: Batch) -> bytes:
        reply = self.inner.exchange(batch)
        self.tap(batch, reply)
        return reply

    def ascii_command(self, letter: str, lines: int = 1) -> list[str]:
        return self.inner.ascii_command(letter, lines)

    def calibrate_proximity(self) -> list[str]:
        return self.inner.calibrate_proximity()

    def waiting_until(self, deadline_s: float) -> None:
        self.inner.waiting_until(deadline_s)

    def close(self) -> None:
        self.inner.close()
