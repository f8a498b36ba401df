"""The ground-sensor module at 0x60 (the same board on the e-puck1 and the e-puck2).

Layout as the e-puck2 firmware reads it, 21 bytes from register 0
(e-puck2_main-processor@d2e0dbb src/sensors/ground.c:15, 34-51): three ground
proximity values (big-endian words, left, centre, right), their three ambient values,
a software revision byte, two cliff proximity and two cliff ambient values. The Pi's
readers take the first six bytes the same way (gctronic/Pi-puck@73b8913
ground-sensor/groundsensor.py:7, 40-44). Values from the e-puck2 model's
``GroundModule`` over the world's floor (firmware_sim.epuck2.sensors).

[inferred]: the revision byte reads 0; the register pointer steps on a burst.
"""

from __future__ import annotations

import struct

from firmware_sim.epuck2.sensors import GroundModule
from firmware_sim.pipuck.registers import RegisterTarget
from firmware_sim.world import World

__all__ = ["GroundSensors"]

BLOCK = 21


class GroundSensors(RegisterTarget):
    """The module's registers 0..20 from the floor under the robot; zeros past them."""

    address = 0x60

    def __init__(self, world: World) -> None:
        super().__init__()
        self.module = GroundModule(world, fitted=True)
        self._block = bytes(BLOCK)

    def snapshot(self) -> None:
        delta, ambient = self.module.delta(), self.module.ambient()
        self._block = (struct.pack(">3H3H", *delta[:3], *ambient[:3]) + b"\0"
                       + struct.pack(">2H2H", *delta[3:], *ambient[3:]))  # fmt: skip

    def get(self, register: int) -> int:
        return self._block[register] if register < BLOCK else 0

    def put(self, register: int, value: int) -> None:
        pass  # nothing to configure
