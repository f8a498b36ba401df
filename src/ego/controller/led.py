"""Webots' ``LED``."""

from __future__ import annotations

import numbers

from ego.controller.device import Device, view

__all__ = ["LED"]


@view("LED")
class LED(Device):
    """An LED: ``set(0)`` off, any other value on (Webots' meaning for the e-puck's LEDs);
    an RGB LED (where the firmware has them: the e-puck2's led1, led3, led5, led7) takes
    its colour, ``set(0xRRGGBB)``, as Webots' RGB LEDs do."""

    def set(self, value: int) -> None:
        """Any number, as Webots takes it (``True`` and ``1.0`` switch it on); strict: ints."""
        if self._strict and (isinstance(value, bool) or not isinstance(value, numbers.Integral)):
            raise TypeError(f"LED value must be an int, not {type(value).__name__}")
        if not isinstance(value, numbers.Real):
            raise TypeError(f"LED value must be a number, not {type(value).__name__}")
        leds = self._core.leds
        if leds.index(self._name) in leds.rgb:
            leds.set(self._name, int(value))
        else:
            leds.set(self._name, 1 if int(value) else 0)

    def get(self) -> int:
        return self._core.leds.get(self._name)

    value = property(lambda self: self.get(), lambda self, v: self.set(v))
