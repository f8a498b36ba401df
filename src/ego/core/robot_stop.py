"""The Robot's safe stop: the confirmed stop batch, and what must be stopped and released."""

from __future__ import annotations

import logging
from dataclasses import dataclass
from typing import TYPE_CHECKING

from ego.core.safety import send_stop
from ego.errors import EgoError

if TYPE_CHECKING:
    from ego.camera import Camera
    from ego.core.backend import Opened
    from ego.core.scheduler import Pacer
    from ego.devices.leds import Leds
    from ego.devices.motors import Motors
    from ego.i2c.side import OveroI2C
    from ego.seam.channel import ChannelBase

__all__ = ["Parts", "SafeStop"]

log = logging.getLogger("ego.core.robot")  # the Robot's own logger, as before the split


class SafeStop:
    """The part of :class:`~ego.core.robot.Robot` that stops the actuators on demand."""

    channel: ChannelBase
    motors: Motors
    leds: Leds

    def stop_actuators(self) -> None:
        """Stop both wheels and switch every LED off now, whatever ego believes their state.

        The batch ends with ``E`` so that the dsPIC answers: the stop is confirmed heard,
        and the speeds it reports must be zero.
        """
        self.motors.stop_request()
        self.leds.all_off()
        with self.channel.lock:
            send_stop(self.channel)

    def send_stop(self) -> None:
        """Send the confirmed stop batch now, from any thread, between two steps' batches
        (ego's view of the actuators is left to the step: a guard keeps them stopped)."""
        with self.channel.lock:
            send_stop(self.channel)


@dataclass
class Parts:
    """What a robot must stop and release, without a reference back to the Robot.

    Held apart from the Robot so that a finalizer can stop the wheels when the Robot is
    dropped without close(), or when the interpreter exits with it still open.
    """

    channel: ChannelBase
    clock: Pacer
    opened: Opened
    i2c: OveroI2C
    camera: Camera | None = None
    lost: bool = False

    def close(self) -> None:
        """Stop the wheels and LEDs (unless the link is lost), then release everything."""
        if not self.lost:
            try:
                send_stop(self.channel)
            except (EgoError, OSError) as exc:
                log.error("could not stop the robot's actuators: %s", exc)
        if self.camera is not None:
            self.camera.close()
        self.clock.close()
        self.i2c.close()
        self.channel.close()
        self.opened.close()
