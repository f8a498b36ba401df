"""The firmware snapshots this emulator was written from (cited as ``MAIN@...:path:line``)."""

from __future__ import annotations

__all__ = ["ESP", "MAIN"]

#: The e-puck2 main processor (STM32F407) firmware, master of 2025-09-03.
MAIN = "e-puck2/e-puck2_main-processor@d2e0dbba8f50a0619b01186c5437e3f5ffffae56"
#: The radio module's (ESP32) WiFi firmware, GCtronic's last commit (2019-02-15), kept in
#: a fork under Projects/ESP32_E-Puck_2/main/.
ESP = "eshjordan/esp-idf@18f3ae6752d73117ebdb1ed7a2e109326d8dbe1b"
