"""Serial ports: a path or any pyserial URL at the firmware's line rate (no scheme).

``/dev/ttyS0`` (the Overo's own UART), ``/dev/rfcomm0`` (Bluetooth), ``socket://``,
``loop://``, ``spy://``: a :class:`~ego.serial.link.Link` over a serial transport.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, ClassVar

from ego.camera.v4l2 import DEFAULT_CAMERA_DEVICE
from ego.core.backend import BackendOptions, Opened, check
from ego.core.ports import default_baud
from ego.seam.profile import Firmware
from ego.serial.link import LinkSettings
from ego.serial.transport import check_baudrate

if TYPE_CHECKING:
    from ego.camera import FrameSource
    from ego.core.environment import Environment
    from ego.i2c.bus import I2CAccess
    from ego.serial.link import Link
    from ego.serial.transport import Transport

__all__ = ["SerialBackend", "SerialOptions", "check_i2c_bus", "open_link", "robot_i2c"]


def check_i2c_bus(bus: object) -> int | str:
    """``bus`` if it names an I2C bus (a number, a ``/dev/i2c-N`` path) or is "none"; else
    OutOfRangeError naming it."""
    from ego.i2c.bus import i2c_bus_path

    if bus == "none":
        return "none"
    i2c_bus_path(bus)  # type: ignore[arg-type]  # it refuses what is not an int or str
    assert isinstance(bus, int | str)
    return bus


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


@dataclass(frozen=True, kw_only=True)
class SerialOptions(BackendOptions):
    """A serial port's options; None: the default each names."""

    #: The line rate (None: the port's own, :func:`ego.core.ports.default_baud`).
    baudrate: int | None = field(default=None, metadata=check(check_baudrate))
    #: How the link retries, resynchronises and reconnects (None: LinkSettings()).
    link_settings: LinkSettings | None = None
    #: The V4L2 camera device, or "none" (None: EGO_CAMERA, else /dev/video0).
    camera_device: str | None = None
    #: The robot's own I2C bus: a number, a ``/dev/i2c-N`` path, or "none" (None: the
    #: Overo's ``/dev/i2c-3`` on its own UART, none elsewhere).
    i2c_bus: int | str | None = field(default=None, metadata=check(check_i2c_bus))

    def with_environment(self, environment: Environment) -> SerialOptions:
        if self.camera_device is not None or environment.camera is None:
            return self
        return dataclasses.replace(self, camera_device=environment.camera)

    def line_baud(self, port: str) -> int:
        """The rate ``port`` opens at: the one given, else the port's own."""
        return self.baudrate if self.baudrate is not None else default_baud(port, self.firmware)


class SerialBackend:
    """A serial port or pyserial URL at the firmware's line rate (docs/protocol.md, Line).

    Options (:class:`SerialOptions`): ``baudrate``, ``link_settings``, ``camera_device``,
    and ``i2c_bus`` (a number, a ``/dev/i2c-N`` path, or "none"), the robot's own I2C bus;
    by default the Overo's ``/dev/i2c-3`` on its own UART (``/dev/ttyS*``), none elsewhere.
    """

    options: ClassVar[type[BackendOptions]] = SerialOptions

    def open(self, port: str, options: BackendOptions) -> Opened:
        from ego.serial.transport import SerialTransport

        given = SerialOptions.narrow(options)
        baud = given.line_baud(port)
        i2c = robot_i2c(port, given.i2c_bus)  # checked before the port opens
        channel = open_link(SerialTransport(port, baud), given.firmware, given.link_settings)
        device = given.camera_device or DEFAULT_CAMERA_DEVICE
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
