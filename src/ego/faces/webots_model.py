"""What Webots' e-puck model (E-puck.proto) says of a family's devices where the kind's
default (the e-puck's infra-red DistanceSensor) does not hold: the Webots face reads it
here, so that the device families (the core) hold no Webots model data.

Sources: Webots' ``projects/robots/gctronic/e-puck/protos/E-puck.proto`` (version "2"):
the ``tof`` DistanceSensor (lookupTable [0 19.8 0, 2 2000 0], aperture 0.44, type
"generic"; what ``getLookupTable`` answers, never applied to the robot's millimetres:
issue 32), and the ``gyro`` (lookupTable [-13.315805 -100000 0.003, 13.315805 100000
0.003]).
"""

from __future__ import annotations

from dataclasses import dataclass

from ego.devices.base import Device

__all__ = ["WEBOTS_MODELS", "WebotsModel", "webots_model"]


@dataclass(frozen=True, slots=True)
class WebotsModel:
    """A family's devices as Webots' PROTO declares them; None: the kind's default."""

    #: The PROTO's lookupTable, (input, value, noise) per row, flattened.
    lookup: tuple[float, ...] | None = None
    #: A distance sensor's aperture, rad.
    aperture_rad: float | None = None
    #: A distance sensor's type: "generic", "infra-red", "sonar", "laser".
    sensor_type: str | None = None


#: By family (``Device.table_family``): the families whose devices Webots models otherwise.
WEBOTS_MODELS: dict[str, WebotsModel] = {
    "tof": WebotsModel(lookup=(0.0, 19.8, 0.0, 2.0, 2000.0, 0.0), aperture_rad=0.44,
                       sensor_type="generic"),
    "gyro": WebotsModel(lookup=(-13.315805, -100000.0, 0.003, 13.315805, 100000.0, 0.003)),
}

_DEFAULT = WebotsModel()


def webots_model(family: Device) -> WebotsModel:
    """What Webots' model says of ``family``'s devices (the kind's defaults if nothing)."""
    return WEBOTS_MODELS.get(type(family).table_family, _DEFAULT)
