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
    from ego.i2c.side import OveroI2C
    from ego.seam.channel import ChannelBase

__all__ = ["Parts"]

log = logging.getLogger("ego.core.robot")  # the Robot's own logger, as before the split


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

    def stop_now(self) -> None:
        """Send the confirmed stop batch now, from any thread, between two steps' batches."""
        with self.channel.lock:
            send_stop(self.channel)

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
