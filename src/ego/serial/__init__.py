"""The serial side of ego: the dsPIC protocol (sans-I/O), transports and the link."""

from ego.seam.batch import Batch, Request
from ego.seam.channel import FirmwareInfo, LinkStats
from ego.seam.profile import Command, Firmware, Profile
from ego.serial.link import Link, LinkSettings
from ego.serial.profiles import PROFILES
from ego.serial.protocol import encode_batch
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
