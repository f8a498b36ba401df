"""The Robot's step: one batch over the link, the I2C bus and the camera, then the wait."""

from __future__ import annotations

import logging
import time
from collections.abc import Callable
from typing import TYPE_CHECKING

from ego.core.transaction import run_step
from ego.devices.base import Device
from ego.devices.i2c_step import run_i2c_step
from ego.errors import LinkLostError, ReplayEndedError
from ego.seam.validate import MAX_PERIOD_MS, check_int

if TYPE_CHECKING:
    from ego.camera import Camera
    from ego.core.robot_stop import Parts
    from ego.core.scheduler import Pacer
    from ego.i2c.side import OveroI2C
    from ego.seam.channel import ChannelBase

__all__ = ["Stepping"]

log = logging.getLogger("ego.core.robot")  # the Robot's own logger, as before the split


class Stepping:
    """The part of :class:`~ego.core.robot.Robot` that runs its time steps."""

    channel: ChannelBase
    clock: Pacer
    i2c: OveroI2C
    families: tuple[Device, ...]
    steps: int
    _closed: bool
    _lost: bool
    _parts: Parts
    _time_ms: int
    _step_parts: tuple[Device, ...]
    _local_devices: list[Camera]
    _reply_clock: Callable[[], float]

    @property
    def time_s(self) -> float:
        """Controller time: the sum of the steps taken, in seconds (Webots' getTime)."""
        return self._time_ms / 1000.0

    @property
    def overruns(self) -> int:
        return self.clock.overruns

    def _run_guards(self) -> None:
        """Call the step guards with the robot (the Robot's own, typed as it)."""
        raise NotImplementedError

    def _run_listeners(self) -> None:
        """Call the step listeners with the robot (the Robot's own, typed as it)."""
        raise NotImplementedError

    def step(self, ms: int) -> int:
        """Run one time step of ``ms`` milliseconds: send what is due, read, wait out the rest.

        Returns 0, or -1 once the link is lost for good (or the robot is closed), like
        Webots' ``step``.
        """
        if self._closed or self._lost:
            return -1
        step_ms = check_int("time step", ms, 1, MAX_PERIOD_MS, " ms")
        self.clock.begin()
        now = self._time_ms
        self._run_guards()
        try:
            with self.channel.lock:
                run_step(self._step_parts, self.channel, now, self._restarted, self._reply_clock)
            # Also where a network channel says its session ended with nothing to send.
            self.channel.waiting_until(time.monotonic() + step_ms / 1000.0)
        except ReplayEndedError as exc:  # a replay's end: over, not broken
            log.info("link lost for good: %s", exc)
            self._lost = self._parts.lost = True
            return -1
        except LinkLostError as exc:
            log.error("link lost for good: %s", exc)
            self._lost = self._parts.lost = True
            return -1
        # Beside the batch: what the firmware leaves on the Overo's I2C bus (its own lock).
        run_i2c_step(self._step_parts, self.i2c, now)
        for local in self._local_devices:  # captured here, not over the link: the camera
            local.update(now)
        self._time_ms += step_ms
        self.steps += 1
        # Listeners run in the step's slack, before its wait: what they cost is hidden
        # in the wait rather than added to the step (a dashboard, a recorder).
        self._run_listeners()
        self.clock.wait(step_ms)
        return 0

    def _restarted(self) -> None:
        profile = self.channel.profile
        for family in self.families:
            family.set_profile(profile)
            for part in family.parts:
                part.reset()
