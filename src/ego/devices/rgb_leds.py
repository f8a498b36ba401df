"""The e-puck2's RGB LEDs: Webots' ``0xRRGGBB`` colours as the firmware's -0x0A request.

Webots' e-puck2 makes led1, led3, led5 and led7 RGB (``LED.set(0xRRGGBB)``); the firmware
calls them LED2, LED4, LED6, LED8 and sets all four at once with ``-0x0A`` and 12 bytes,
R, G, B of each in 0..100 % (MAIN:src/epuck1x/Asercom2.c:574-588, src/leds.h:10). An
``L`` on them would set only the red channel, at 10 % (e_led.c:24-74): the
:class:`~ego.devices.leds.Leds` family sends them this way instead, where the profile
names them (``Profile.rgb_leds``).
"""

from __future__ import annotations

from collections.abc import Sequence

from ego.seam.batch import Request
from ego.seam.profile import Command
from ego.serial.asercom2 import rgb_percent

__all__ = ["MAX_COLOUR", "colour_request", "rgb_percent"]

#: The largest colour Webots' LED.set takes on an RGB LED.
MAX_COLOUR = 0xFFFFFF


def colour_request(colours: Sequence[int]) -> Request:
    """The ``-0x0A`` request setting the RGB LEDs, in the profile's order, to ``colours``
    (each ``0xRRGGBB``; 255 becomes 100 %, each byte rounded to the nearest percent)."""
    return Request(Command.RGB_LEDS, tuple(p for c in colours for p in rgb_percent(c)))
