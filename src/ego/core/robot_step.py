"""The Robot's step: one batch over the link, the I2C bus and the camera, then the wait."""

from __future__ import annotations

import logging
import time
from collections.abc import Callable
from typing import TYPE_CHECKING, Generic, TypeVar

from ego.core.transaction import run_step
from ego.devices.i2c_step import run_i2c_step
from ego.errors import LinkLostError, ReplayEndedError
from ego.seam.validate import MAX_PERIOD_MS, check_int

if TYPE_CHECKING:
    from ego.camera import Camera
    from ego.core.robot_devices import RobotDevices
    from ego.core.robot_stop import Parts
    from ego.core.scheduler import Pacer
    from ego.seam.channel import ChannelBase

__all__ = ["Stepper"]

#: What the hooks are called with: the robot stepping.
_Host = TypeVar("_Host")

log = logging.getLogger("ego.core.robot")  # the Robot's own logger, as before the split


class Stepper(Generic[_Host]):
    """Runs a robot's time steps over what it is handed: the robot's devices, the parts it
    must stop (its clock, I2C side, and whether the link is lost), its local devices (the
    camera, once opened) and the clock replies are timed on.

    The Robot owns one and hands it, each step, the channel (a recording may have tapped
    it) and itself, for the hooks run before the batch (guards) and in the step's slack
    (listeners).
    """

    def __init__(
        self,
        devices: RobotDevices,
        parts: Parts,
        reply_clock: Callable[[], float],
    ) -> None:
        self._devices = devices
        self._parts = parts
        self._reply_clock = reply_clock
        #: Devices scheduled on this side of the link (the camera, once opened): each is
        #: updated with the step's time.
        self.local_devices: list[Camera] = []
        #: Controller time in ms: the sum of the steps taken (Webots' getTime, in ms).
        self.time_ms = 0
        #: How many steps ran to their end.
        self.steps = 0
        #: Called with the robot before every step's batch, after the controller's own
        #: commands: what they set wins (a dashboard's stop and drive).
        self.guards: list[Callable[[_Host], None]] = []
        #: Called with the robot after every step's exchange, in its slack before the wait.
        self.listeners: list[Callable[[_Host], None]] = []

    @property
    def clock(self) -> Pacer:
        return self._parts.clock

    def step(self, ms: int, channel: ChannelBase, robot: _Host) -> int:
        """Run one time step of ``ms`` milliseconds: send what is due, read, wait out the rest.

        Returns 0, or -1 once the link is lost for good, like Webots' ``step``.
        """
        if self._parts.lost:
            return -1
        step_ms = check_int("time step", ms, 1, MAX_PERIOD_MS, " ms")
        self.clock.begin()
        deadline_s = time.monotonic() + step_ms / 1000.0  # the I2C reads' too
        now = self.time_ms
        for guard in self.guards:
            guard(robot)
        parts = self._devices.step_parts
        try:
            with channel.lock:
                run_step(parts, channel, now, self._restarted, self._reply_clock)
            # Also where a network channel says its session ended with nothing to send.
            channel.waiting_until(time.monotonic() + step_ms / 1000.0)
        except ReplayEndedError as exc:  # a replay's end: over, not broken
            log.info("link lost for good: %s", exc)
            self._parts.lost = True
            return -1
        except LinkLostError as exc:
            log.error("link lost for good: %s", exc)
            self._parts.lost = True
            return -1
        # Beside the batch: what the firmware leaves on the Overo's I2C bus (its own lock).
        run_i2c_step(parts, self._parts.i2c, now, deadline_s=deadline_s)
        for local in self.local_devices:  # captured here, not over the link: the camera
            local.update(now)
        self.time_ms += step_ms
        self.steps += 1
        # Listeners run in the step's slack, before its wait: what they cost is hidden
        # in the wait rather than added to the step (a dashboard, a recorder).
        for listener in self.listeners:
            listener(robot)
        self.clock.wait(step_ms)
        return 0

    def _restarted(self) -> None:
        self._devices.restarted(self._parts.channel.profile)
