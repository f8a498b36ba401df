"""The serial side of ego: the dsPIC protocol (sans-I/O), transports and the link."""

from ego.core.channel import FirmwareInfo, LinkStats
from ego.serial.link import Link, LinkSettings
from ego.serial.protocol import (
    PROFILES,
    Batch,
    Command,
    Firmware,
    Profile,
    Request,
    encode_batch,
)
from ego.serial.transport import SerialTransport, Transport

__all__ = [
    "PROFILES",
    "Batch",
    "Command",
    "Firmware",
    "FirmwareInfo",
    "Link",
    "LinkSettings",
    "LinkStats",
    "Profile",
    "Request",
    "SerialTransport",
    "Transport",
    "encode_batch",
]
