"""The e-puck2's LEDs: four red (LED1, 3, 5, 7), four RGB (LED2, 4, 6, 8, each channel
0..100 %), the body and the front LED (MAIN:src/leds.c, leds.h), and the e-puck1 LED
calls asercom goes through (MAIN:src/epuck1x/motor_led/advance_one_timer/e_led.c)."""

from __future__ import annotations

import threading

from firmware_sim.world import World

__all__ = ["RGB_INTENSITY", "Leds"]

#: e_led.c:13: an odd e-puck1 LED number lights its RGB LED's red channel at 10 %.
RGB_INTENSITY = 10
RED = 0


class Leds:
    """LED state, mirrored into the world's ten on/off LEDs (ring 0..7, body 8, front 9)."""

    def __init__(self, world: World) -> None:
        self.world = world
        self._lock = threading.RLock()
        #: LED1, LED3, LED5, LED7 (front, right, back, left): on or off.
        self.red = [False] * 4
        #: LED2, LED4, LED6, LED8: [red, green, blue], each a uint8 (meant as 0..100 %).
        self.rgb = [[0, 0, 0] for _ in range(4)]
        self.body = False
        self.front = False

    # -- MAIN:src/leds.c ------------------------------------------------------------

    def set_led(self, index: int, value: int) -> None:
        """leds.c:8-43: a red LED 0..3 on (1), off (0) or toggled (>1); any other index
        sets all four."""
        with self._lock:
            for i in [index] if 0 <= index < 4 else range(4):
                self.red[i] = (not self.red[i]) if value > 1 else bool(value)
            self._mirror()

    def set_rgb_led(self, index: int, red: int, green: int, blue: int) -> None:
        """leds.c:45-52: the three channels, each cast to uint8."""
        with self._lock:
            self.rgb[index] = [red & 0xFF, green & 0xFF, blue & 0xFF]
            self._mirror()

    def toggle_rgb_red(self, index: int, intensity: int) -> None:
        """leds.c:54-63: the red channel to 0 if lit, else to ``intensity``."""
        with self._lock:
            channel = self.rgb[index]
            channel[RED] = 0 if channel[RED] > 0 else intensity
            self._mirror()

    def set_body_led(self, value: int) -> None:
        """leds.c:71-77: on, off, or toggled (>1)."""
        with self._lock:
            self.body = (not self.body) if value > 1 else bool(value)
            self._mirror()

    def set_front_led(self, value: int) -> None:
        """leds.c:85-91."""
        with self._lock:
            self.front = (not self.front) if value > 1 else bool(value)
            self._mirror()

    def clear_leds(self) -> None:
        """leds.c:93-99: red and RGB off; the body and front LEDs are left alone."""
        with self._lock:
            for i in range(4):
                self.set_led(i, 0)
                self.set_rgb_led(i, 0, 0, 0)

    # -- MAIN:src/epuck1x/motor_led/advance_one_timer/e_led.c ------------------------

    def e_set_led(self, number: int, value: int) -> None:
        """e_led.c:24-74: even numbers are the red LEDs, odd ones only the red channel of
        an RGB LED at 10 % (toggled when value >= 2); 8 and above set all eight."""
        number &= 0xFFFFFFFF  # unsigned int parameters
        value &= 0xFFFFFFFF
        with self._lock:
            if number > 7:
                for i in range(8):
                    self.e_set_led(i, value)
            elif number % 2 == 0:
                self.set_led(number // 2, value)
            elif value >= 2:
                self.toggle_rgb_red(number // 2, RGB_INTENSITY)
            else:
                self.set_rgb_led(number // 2, value * RGB_INTENSITY, 0, 0)

    def _mirror(self) -> None:
        for i in range(4):
            self.world.set_led(2 * i, 1 if self.red[i] else 0)
            self.world.set_led(2 * i + 1, 1 if any(self.rgb[i]) else 0)
        self.world.set_led(8, 1 if self.body else 0)
        self.world.set_led(9, 1 if self.front else 0)
