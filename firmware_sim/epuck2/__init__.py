"""An emulated GCtronic e-puck2 (main processor asercom v2 on a pty, the radio's WiFi
protocol on TCP), written from the firmware sources and apart from ego."""

from firmware_sim.epuck2.emulator import (
    BLUETOOTH_SELECTOR,
    USB_SELECTOR,
    WIFI_SELECTOR,
    Epuck2Emulator,
)
from firmware_sim.epuck2.robot import Epuck2Robot

__all__ = [
    "BLUETOOTH_SELECTOR",
    "USB_SELECTOR",
    "WIFI_SELECTOR",
    "Epuck2Emulator",
    "Epuck2Robot",
]
