"""``epuck2://HOST[:PORT]``: a GCtronic e-puck2 over WiFi (selector 15, the radio
module's WiFi firmware, TCP port 1000 by default).

``HOST`` is a name or an address, resolved once when the robot opens (the firmware has
no discovery: docs/guide/epuck2.md says how to find the address). The channel
(:class:`~ego.backends.epuck2.channel.Epuck2Channel`) keeps reading the robot's stream,
sends each one-shot once, never connects without a valid command, sees its stop
answered before it closes and reconnects after a drop; the camera
(:class:`~ego.backends.epuck2.camera.WifiCamera`) is the stream's 160x120 image.

>>> with ego.Robot("epuck2://192.168.1.1") as robot:  # doctest: +SKIP
...     robot.motors.set_speeds(200, 200)
"""

from __future__ import annotations

import math
import socket
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import ClassVar
from urllib.parse import urlsplit

from ego.backends.epuck2.camera import WifiCamera
from ego.backends.epuck2.channel import Epuck2Channel, WifiSettings
from ego.backends.epuck2.requests import WIFI_PROFILE
from ego.backends.epuck2.wifi_packets import DEFAULT_PORT
from ego.core.backend import BackendOptions, Opened, check
from ego.errors import BackendOptionError, PortNotFoundError

__all__ = ["Epuck2Backend", "Epuck2Options", "parse_port", "probe", "resolve"]

SCHEME = "epuck2"


def _seconds(name: str) -> Callable[[object], float]:
    def checked(value: object) -> float:
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise BackendOptionError(f"epuck2 option {name}={value!r} must be a number of seconds")
        if not (math.isfinite(value) and value > 0):
            raise BackendOptionError(f"epuck2 option {name}={value!r} must be above 0 s")
        return float(value)

    return checked


@dataclass(frozen=True, kw_only=True)
class Epuck2Options(BackendOptions):
    """An e-puck2's WiFi options, in seconds; None: the default each names."""

    #: To connect, and for each awaited reply (None: 2 s).
    timeout_s: float | None = field(default=None, metadata=check(_seconds("timeout_s")))
    #: To be back after a drop before LinkLostError (None: 5 s).
    reconnect_s: float | None = field(default=None, metadata=check(_seconds("reconnect_s")))
    #: For the stop's answer at close (None: 1 s).
    stop_timeout_s: float | None = field(default=None, metadata=check(_seconds("stop_timeout_s")))

    def settings(self) -> WifiSettings:
        default = WifiSettings()
        return WifiSettings(
            self.timeout_s or default.timeout_s,
            self.reconnect_s or default.reconnect_s,
            self.stop_timeout_s or default.stop_timeout_s,
        )


def parse_port(port: str) -> tuple[str, int]:
    """(host, TCP port) of ``epuck2://HOST[:PORT]``; PortNotFoundError for anything else."""
    try:
        parts = urlsplit(port)
        host, number = parts.hostname, parts.port
    except ValueError as exc:
        raise PortNotFoundError(f"{port!r} is not epuck2://HOST[:PORT]: {exc}") from None
    if parts.scheme != SCHEME or not host or parts.path not in ("", "/") or parts.query:
        raise PortNotFoundError(f"{port!r} is not epuck2://HOST[:PORT]")
    return host, DEFAULT_PORT if number is None else number


def resolve(port: str) -> tuple[str, int]:
    """The address ``port`` names, resolved once; PortNotFoundError naming the host."""
    host, number = parse_port(port)
    try:
        found = socket.getaddrinfo(host, number, socket.AF_INET, socket.SOCK_STREAM)
    except OSError as exc:
        raise PortNotFoundError(f"{port}: cannot resolve {host!r}: {exc}") from None
    address = found[0][4]
    return str(address[0]), int(address[1])


def probe(port: str, timeout_s: float = 1.0) -> bool:
    """Whether an e-puck2's radio answers at ``port`` within ``timeout_s``.

    A probe may not connect and leave: the radio would wedge (socket_e-puck2.c:164-196).
    So it sends a valid command at once, the stop (every actuator off) with the request
    byte 0, waits for its empty ``0x03`` reply, and only then closes: probing a robot
    stops it. An address that cannot be resolved or reached is simply not a robot.
    """
    from ego.backends.epuck2.connection import WifiConnection, connect
    from ego.backends.epuck2.wifi_packets import Request, encode_command
    from ego.errors import LinkError
    from ego.serial.asercom2 import Actuators, encode_actuators

    stop = encode_command(Request(0), encode_actuators(Actuators()))
    try:
        conn = WifiConnection(port, connect(port, resolve(port), stop, timeout_s))
    except LinkError:
        return False
    try:
        heard = conn.wait("empties", 0, time.monotonic() + timeout_s)
        return heard is not None and heard.empties > 0
    finally:
        conn.close()


class Epuck2Backend:
    """``Robot("epuck2://HOST[:PORT]")``. Options (:class:`Epuck2Options`): ``timeout_s``,
    ``reconnect_s``, ``stop_timeout_s``; ``firmware`` may only name the e-puck2's."""

    options: ClassVar[type[BackendOptions]] = Epuck2Options

    def open(self, port: str, options: BackendOptions) -> Opened:
        given = Epuck2Options.narrow(options)
        if given.firmware is not None and given.firmware is not WIFI_PROFILE.firmware:
            raise BackendOptionError(
                f"{port}: an e-puck2 over WiFi speaks its radio's protocol, not the "
                f"{given.firmware} firmware's: leave firmware unset"
            )
        channel = Epuck2Channel(port, resolve(port), given.settings())

        def camera() -> WifiCamera:
            return WifiCamera(channel)

        return Opened(channel, camera, remote=True)
