"""The e-puck2's time-of-flight distance sensor, ``tof`` (wire command -0x0D).

The VL53L0X in the e-puck2's front measures up to about 2 m and the firmware answers its
last range in millimetres (MAIN:src/epuck1x/Asercom2.c:612-621, ``VL53L0X_get_dist_mm``).
Webots' e-puck2 (E-puck.proto, version "2") has it as a DistanceSensor ``tof`` (aperture
0.44 rad) whose lookup table maps 0..2 m to 19.8..2000. That table models the sensor in
simulation: a real robot's reading is already what the table stands for. Webots' own
e-puck2 remote control hands the robot's millimetres to ``getValue`` unchanged
(cyberbotics/webots@d33882c:projects/robots/gctronic/e-puck/plugins/remote_controls/
e-puck_wifi/Wrapper.cpp, ``robotStep``: bytes 69-70 of the sensor packet go to
``wbr_distance_sensor_set_value`` as they are), as it does ps0..ps7; so does ego (issue 32).
The PROTO's table is what the Webots face's ``getLookupTable`` answers
(ego.faces.webots_model), never applied to the robot's millimetres.
"""

from __future__ import annotations

from typing import ClassVar

from ego.devices.base import ArraySensor
from ego.devices.table import TABLE, Series
from ego.seam.profile import Command

__all__ = ["TofSensor"]


@TABLE.declare("tof", webots_rank=9, series=Series("ToF distance", "mm", ("tof",)))
class TofSensor(ArraySensor):
    """The distance to what is in front, in mm (about 0..2000; 8190 when nothing is in range).

    >>> robot.tof.enable(100)                            # doctest: +SKIP
    >>> robot.step(100); robot.tof.value("tof")
    412
    """

    family = "ToF distance sensor"
    command = Command.TOF
    #: The VL53L0X answers 8190 (8191 at most) when nothing reflects (its no-target value).
    value_range: ClassVar[tuple[int, int]] = (0, 8191)

    @property
    def member_names(self) -> tuple[str, ...]:
        return self.served_names()

    @property
    def distance_mm(self) -> int:
        """The last distance in mm."""
        return self.values[0]
