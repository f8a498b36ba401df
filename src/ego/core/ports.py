"""Where to connect: the port a Robot opens when none is named, and its line rate."""

from __future__ import annotations

import os

from ego.errors import PortNotFoundError
from ego.seam.profile import DEFAULT_BAUD, Firmware
from ego.serial.profiles import PROFILES

__all__ = [
    "BLUETOOTH_PORT_PREFIX",
    "DEFAULT_PORT",
    "ROBOT_UART_PREFIXES",
    "call_baud",
    "default_baud",
    "is_robot_uart",
    "resolve_port",
]

#: The Overo's UART to the dsPIC.
DEFAULT_PORT = "/dev/ttyS0"


def resolve_port(port: str | os.PathLike[str] | None, fallback: str | None = None) -> str:
    """The argument, else ``fallback`` (``EGO_PORT``, as :mod:`ego.core.environment` read
    it), else ``/dev/ttyS0``."""
    if isinstance(port, os.PathLike):
        port = os.fspath(port)
    if port is not None and not isinstance(port, str):
        raise TypeError(
            "port must be a string (a serial port, a pyserial URL, 'sim', tcp:// or udp://), "
            f"not {type(port).__name__}"
        )
    if port is not None and not port.strip():
        raise PortNotFoundError(
            f"port {port!r} is empty: give a serial port (/dev/ttyS0), a pyserial URL, "
            "'sim', tcp://HOST:PORT or udp://HOST:PORT, or None for $EGO_PORT"
        )
    return port or fallback or DEFAULT_PORT


#: Where Linux puts a Bluetooth serial link (rfcomm bind / rfcomm connect).
BLUETOOTH_PORT_PREFIX = "/dev/rfcomm"


def default_baud(port: str, firmware: Firmware | None) -> int:
    """The line rate to open ``port`` at when the caller names none (docs/protocol.md, Line).

    A named firmware's own rate (Webots' answers at 115200 only, the stock firmware at
    230400 on the Overo's UART2); else 115200 for a Bluetooth port and 230400 for the rest.
    """
    if firmware is not None:
        return PROFILES[firmware].line_baud
    if port.startswith(BLUETOOTH_PORT_PREFIX):
        return PROFILES[Firmware.WEBOTS].line_baud
    return DEFAULT_BAUD


#: The robot's own UARTs as the Overo names them: a port there means ego runs on the robot.
ROBOT_UART_PREFIXES = ("/dev/ttyS", "/dev/ttyO")


def is_robot_uart(port: str) -> bool:
    """Whether ``port`` is the Overo's own UART to the dsPIC (/dev/ttyS*, /dev/ttyO*)."""
    return port.startswith(ROBOT_UART_PREFIXES)


def call_baud(port: str, firmware: Firmware | None, asked: int | None) -> int | None:
    """The rate a controller's own serial call asks for (E-GO's ``overo_serial_init(230400,
    ...)``), where it applies: the Overo's own UART with the stock firmware (or a firmware
    to detect there). Elsewhere None, the port's own rate (:func:`default_baud`): Webots'
    firmware answers at 115200 only, a Bluetooth link runs at 115200, and the line of a
    served robot, a Zenoh node or a recording is not this controller's to set."""
    if asked is None or not is_robot_uart(port) or firmware is Firmware.WEBOTS:
        return None
    return asked
