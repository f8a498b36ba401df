"""A robot served by ``ego serve``: ``tcp://``, ``udp://`` and ``unix://`` ports."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, ClassVar

from ego.backends.serial_line import check_i2c_bus, robot_i2c
from ego.core.backend import BackendOptions, Opened, check
from ego.errors import FirmwareMismatchError
from ego.serial.link import LinkSettings

if TYPE_CHECKING:
    from ego.core.environment import Environment

__all__ = ["RemoteBackend", "RemoteOptions"]


@dataclass(frozen=True, kw_only=True)
class RemoteOptions(BackendOptions):
    """A served robot's options; None: the default each names."""

    #: The shared secret (None: EGO_SECRET_FILE's, else EGO_SECRET, else none).
    secret: str | bytes | None = None
    #: Accepted for controllers written for a serial line (E-GO's
    #: ``overo_serial_init(230400, ...)``): the server owns that line and its rate.
    baudrate: int | None = None
    #: How the client retries and reconnects (None: LinkSettings()).
    link_settings: LinkSettings | None = None
    #: The robot's own I2C bus (None: this machine's /dev/i2c-3 for unix://, else none).
    i2c_bus: int | str | None = field(default=None, metadata=check(check_i2c_bus))
    #: How long one request may take, in seconds (None: 5).
    timeout_s: float | None = None
    #: Whether a thread keeps the session alive between steps (None: yes).
    heartbeat: bool | None = None
    #: How long connecting may take, in seconds (None: 2); over UDP the handshake is sent
    #: again until then.
    connect_timeout_s: float | None = None
    #: How long a UDP request waits before it is sent again, in seconds (None: 0.02).
    retransmit_s: float | None = None
    #: How many times a UDP step's request is sent again (None: 8).
    retries: int | None = None

    def with_environment(self, environment: Environment) -> RemoteOptions:
        if self.secret is not None:
            return self
        return dataclasses.replace(self, secret=environment.load_secret())


#: The options that go to the connection as they are, when given.
_CONNECTION = ("timeout_s", "heartbeat", "connect_timeout_s", "retransmit_s", "retries")


class RemoteBackend:
    """A robot served by ``ego serve`` (``tcp://HOST:PORT``, ``udp://HOST:PORT``).

    Options: :class:`RemoteOptions`. A ``unix://`` server runs on this machine (``ego
    run``'s supervisor on the robot), so the robot's own I2C bus is this machine's
    (``i2c_bus``, default ``/dev/i2c-3``); a network port reaches none.
    """

    options: ClassVar[type[BackendOptions]] = RemoteOptions

    def open(self, port: str, options: BackendOptions) -> Opened:
        from ego.backends.remote.channel import RemoteChannel
        from ego.i2c.bus import DEFAULT_I2C_BUS

        given = RemoteOptions.narrow(options)
        i2c_bus = given.i2c_bus
        if i2c_bus is None and port.startswith("unix://"):
            i2c_bus = DEFAULT_I2C_BUS
        i2c = robot_i2c(port, i2c_bus)
        connection = {
            name: value for name in _CONNECTION if (value := getattr(given, name)) is not None
        }
        channel = RemoteChannel.from_url(
            port, given.secret, settings=given.link_settings, **connection
        )
        firmware = given.firmware
        if firmware is not None and channel.info.firmware is not firmware:
            channel.close()
            raise FirmwareMismatchError(
                f"{port} serves a robot with the {channel.info.firmware} firmware, not {firmware}"
            )
        return Opened(channel, channel.frame_source, remote=True, i2c=i2c)
