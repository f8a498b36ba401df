"""The ground-truth devices a Webots world puts in its E-puck's slots: a ``GPS`` or a
``Compass`` in ``turretSlot`` or ``groundSensorsSlot``, as published localisation labs
add them (``E-puck { turretSlot [ GPS { } Compass { } ] }``).

Webots' E-puck PROTO (projects/robots/gctronic/e-puck/protos/E-puck.proto) places each
slot's children in a Transform of the robot: the turret slot at (-0.0095, 0, 0.0486) m,
the ground sensors' slot at (0.03, 0, 0.0003) m, in the robot's frame (x forward, y left,
z up). A device's own ``translation`` adds to its slot's. A GPS reads where its origin
is, so the emulator serves it from the robot's pose offset by that mount
(firmware_sim.true_devices).
"""

from __future__ import annotations

from firmware_sim.wbt_node import Node

__all__ = ["SLOTS", "slot_devices"]

#: Each slot of the E-puck PROTO and where its Transform sits on the robot (m).
SLOTS = {"turretSlot": (-0.0095, 0.0, 0.0486), "groundSensorsSlot": (0.03, 0.0, 0.0003)}
#: The slot devices the emulator serves, by node type, and the name each must have
#: (Webots' default for the node): the name ``getDevice`` finds it by.
_SERVED = {"GPS": "gps", "Compass": "compass"}


def slot_devices(epuck: Node) -> tuple[dict[str, tuple[float, float, float]], list[str]]:
    """The GPS and Compass in the E-puck's slots, each with where it sits on the robot
    (m, x forward, y left, z up), and a note for each other node the slots hold."""
    mounts: dict[str, tuple[float, float, float]] = {}
    notes: list[str] = []
    for slot, (sx, sy, sz) in SLOTS.items():
        children = epuck.fields.get(slot) or []
        for child in children if isinstance(children, list) else [children]:
            if not isinstance(child, Node):
                continue
            name = _SERVED.get(child.type)
            if name is None:
                notes.append(f"skipped {child.type} in E-puck.{slot}")
                continue
            where = f"E-puck.{slot} {child.type}"
            given = child.fields.get("name", [name])
            if given != [name]:
                raise ValueError(f"{where}.name {given!r}: the emulator serves a {child.type} "
                                 f"named {name!r} (Webots' default name)")  # fmt: skip
            rotation = child.numbers("rotation", 4, (0.0, 0.0, 1.0, 0.0))
            if abs(rotation[3]) > 1e-6:
                turn = " ".join(f"{v:g}" for v in rotation)
                raise ValueError(f"{where}.rotation {turn}: a device turned on the robot is "
                                 "not modelled (it reads in the robot's own axes)")  # fmt: skip
            x, y, z = child.numbers("translation", 3, (0.0, 0.0, 0.0))
            mounts[name] = (sx + x, sy + y, sz + z)
    return mounts, notes
