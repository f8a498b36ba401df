"""A bodiless supervisor of a Webots world file: a ``Robot { supervisor TRUE controller
"NAME" }`` node, as deepbots' emitter/receiver examples and evolutionary experiments
place one beside their robots.

Webots runs its controller as it runs the robots', with no body to sense or to bump
into: the emulator keeps the node's name, DEF name, controller and pose (where its
radio's signal strength is measured from). Its children are not read: its controller
gets ego's Emitter and Receiver, as every swarm member does, on channel 1 (the e-puck's
default) until it sets another. A ``Robot`` that is not a supervisor is not modelled.
"""

from __future__ import annotations

from dataclasses import dataclass

from firmware_sim.wbt_node import Node
from firmware_sim.wbt_solids import yaw
from firmware_sim.world import Pose

__all__ = ["MAX_SUPERVISORS", "Bodiless", "bodiless"]

#: Bodiless supervisors a world may hold.
MAX_SUPERVISORS = 8


@dataclass(frozen=True)
class Bodiless:
    """A ``Robot { supervisor TRUE }`` node: what runs it and where it stands."""

    #: Its ``name`` field ("robot" when not given, as Webots').
    name: str
    #: Its DEF name, if it has one.
    def_name: str | None
    #: Its ``controller`` field: a folder of the world's ``controllers`` (Webots' layout).
    controller: str
    pose: Pose


def _text(node: Node, key: str, default: str) -> str:
    value = node.fields.get(key)
    if isinstance(value, list) and len(value) == 1:
        value = value[0]
    if value is None:
        return default
    if not isinstance(value, str) or not value or len(value) > 128:
        raise ValueError(f"Robot.{key} must be a name of 1..128 characters, not {value!r}"[:200])
    return value


def bodiless(node: Node) -> Bodiless | None:
    """The bodiless supervisor ``node`` is (a ``Robot`` whose ``supervisor`` is TRUE), or
    None for any other node."""
    if node.type != "Robot" or node.fields.get("supervisor") not in (True, [True]):
        return None
    x, y, _ = node.numbers("translation", 3, (0.0, 0.0, 0.0))
    turn = yaw(node.numbers("rotation", 4, (0.0, 0.0, 1.0, 0.0)), "Robot.rotation")
    controller = _text(node, "controller", "")
    if not controller or controller == "<extern>":
        raise ValueError(f"Robot {node.name or ''} supervisor TRUE: its controller field "
                         f"{controller!r} names no controller folder to run")  # fmt: skip
    return Bodiless(_text(node, "name", "robot"), node.name, controller, Pose(x, y, turn))
