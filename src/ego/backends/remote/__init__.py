"""A robot served by ``ego serve``: ``tcp://``, ``udp://`` and ``unix://`` ports."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from ego.backends import Opened
from ego.backends.serial_line import robot_i2c
from ego.errors import FirmwareMismatchError
from ego.serial.protocol import Firmware

if TYPE_CHECKING:
    from ego.serial.link import LinkSettings

__all__ = ["RemoteBackend"]


class RemoteBackend:
    """A robot served by ``ego serve`` (``tcp://HOST:PORT``, ``udp://HOST:PORT``).

    ``baudrate`` is accepted for controllers written for a serial line (E-GO's
    ``overo_serial_init(230400, ...)``): the server owns that line and its rate. A
    ``unix://`` server runs on this machine (``ego run``'s supervisor on the robot), so
    the robot's own I2C bus is this machine's (``i2c_bus``, default ``/dev/i2c-3``); a
    network port reaches none.
    """

    def open(
        self,
        port: str,
        *,
        firmware: Firmware | None,
        secret: str | bytes | None = None,
        baudrate: int | None = None,
        link_settings: LinkSettings | None = None,
        i2c_bus: int | str | None = None,
        **connection: Any,
    ) -> Opened:
        from ego.backends.remote.channel import RemoteChannel
        from ego.i2c.bus import DEFAULT_I2C_BUS

        if i2c_bus is None and port.startswith("unix://"):
            i2c_bus = DEFAULT_I2C_BUS
        i2c = robot_i2c(port, i2c_bus)

        channel = RemoteChannel.from_url(port, secret, settings=link_settings, **connection)
        if firmware is not None and channel.info.firmware is not firmware:
            channel.close()
            raise FirmwareMismatchError(
                f"{port} serves a robot with the {channel.info.firmware} firmware, not {firmware}"
            )
        return Opened(channel, channel.frame_source, remote=True, i2c=i2c)
