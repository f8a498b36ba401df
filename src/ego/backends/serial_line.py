"""Serial ports: a path or any pyserial URL at the firmware's line rate (no scheme).

``/dev/ttyS0`` (the Overo's own UART), ``/dev/rfcomm0`` (Bluetooth), ``socket://``,
``loop://``, ``spy://``: a :class:`~ego.serial.link.Link` over a serial transport.
"""

from __future__ import annotations

import os
from typing import TYPE_CHECKING

from ego.backends import Opened
from ego.core.ports import DEFAULT_CAMERA_DEVICE
from ego.serial.protocol import Firmware

if TYPE_CHECKING:
    from ego.camera import FrameSource
    from ego.i2c.bus import I2CAccess
    from ego.serial.link import Link, LinkSettings
    from ego.serial.transport import Transport

__all__ = ["SerialBackend", "open_link", "robot_i2c"]


def robot_i2c(port: str, i2c_bus: int | str | None) -> I2CAccess | None:
    """The I2C bus a robot on ``port`` reaches: ``i2c_bus`` if given ("none": none), else
    the Overo's ``/dev/i2c-3`` when ``port`` is its own UART (ego runs on the robot)."""
    from ego.core.ports import is_robot_uart
    from ego.i2c.bus import DEFAULT_I2C_BUS, local_bus

    if i2c_bus == "none":
        return None
    if i2c_bus is not None:
        return local_bus(i2c_bus)
    return local_bus(DEFAULT_I2C_BUS) if is_robot_uart(port) else None


class SerialBackend:
    """A serial port or pyserial URL at the firmware's line rate (docs/protocol.md, Line).

    ``i2c_bus`` (a number, a ``/dev/i2c-N`` path, or "none") is the robot's own I2C bus;
    by default the Overo's ``/dev/i2c-3`` on its own UART (``/dev/ttyS*``), none elsewhere.
    """

    def open(
        self,
        port: str,
        *,
        firmware: Firmware | None,
        baudrate: int | None = None,
        link_settings: LinkSettings | None = None,
        camera_device: str | None = None,
        i2c_bus: int | str | None = None,
    ) -> Opened:
        from ego.core.ports import default_baud
        from ego.serial.transport import SerialTransport, check_baudrate

        baud = check_baudrate(baudrate) if baudrate is not None else default_baud(port, firmware)
        i2c = robot_i2c(port, i2c_bus)  # checked before the port opens
        channel = open_link(SerialTransport(port, baud), firmware, link_settings)
        device = camera_device or os.environ.get("EGO_CAMERA") or DEFAULT_CAMERA_DEVICE
        if device == "none":
            return Opened(channel, i2c=i2c)

        def camera() -> FrameSource:
            from ego.camera import V4L2Source

            return V4L2Source(device)

        return Opened(channel, camera, i2c=i2c)


def open_link(
    transport: Transport, firmware: Firmware | None, settings: LinkSettings | None = None
) -> Link:
    """A Link over ``transport``; the transport is closed if the dsPIC cannot be reached."""
    from ego.serial.link import Link

    try:
        return Link(transport, firmware, settings)
    except BaseException:
        transport.close()
        raise
