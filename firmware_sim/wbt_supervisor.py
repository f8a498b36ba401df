"""A bodiless supervisor of a Webots world file: a ``Robot { supervisor TRUE controller
"NAME" }`` node, as deepbots' emitter/receiver examples and evolutionary experiments
place one beside their robots.

Webots runs its controller as it runs the robots', with no body to sense or to bump
into: the emulator keeps the node's name, DEF name, controller and pose (where its
radio's signal strength is measured from), and the ``channel`` fields of the
``Emitter`` and ``Receiver`` among its children (0 when not given, as Webots' nodes
default): its controller's Emitter and Receiver start there, as an E-puck's start at its
``emitter_channel`` and ``receiver_channel`` (:func:`epuck_channels`). Its other
children are not read. A ``Robot`` that is not a supervisor is not modelled.
"""

from __future__ import annotations

from dataclasses import dataclass

from firmware_sim.wbt_node import Node
from firmware_sim.wbt_solids import yaw
from firmware_sim.world import Pose

__all__ = ["MAX_SUPERVISORS", "Bodiless", "bodiless", "epuck_channels"]

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
    #: Its Emitter's and Receiver's ``channel`` fields (0 when not given, as Webots'
    #: nodes default); None where it has no such child.
    emitter_channel: int | None = None
    receiver_channel: int | None = None


def _text(node: Node, key: str, default: str) -> str:
    value = node.fields.get(key)
    if isinstance(value, list) and len(value) == 1:
        value = value[0]
    if value is None:
        return default
    if not isinstance(value, str) or not value or len(value) > 128:
        raise ValueError(f"Robot.{key} must be a name of 1..128 characters, not {value!r}"[:200])
    return value


def _channel(value: float, what: str) -> int:
    if not value.is_integer():
        raise ValueError(f"{what} {value:g} is not a whole number")
    return int(value)


def _child_channel(node: Node, kind: str) -> int | None:
    children = node.fields.get("children") or []
    for child in children if isinstance(children, list) else [children]:
        if isinstance(child, Node) and child.type == kind:
            return _channel(child.numbers("channel", 1, (0.0,), -1, 1e9)[0], f"{kind}.channel")
    return None


def epuck_channels(node: Node) -> tuple[int, int]:
    """An ``E-puck``'s ``emitter_channel`` and ``receiver_channel`` (1 by default, as the
    PROTO's)."""
    return (
        _channel(node.numbers("emitter_channel", 1, (1.0,), -1, 1e9)[0], "E-puck.emitter_channel"),
        _channel(node.numbers("receiver_channel", 1, (1.0,), -1, 1e9)[0],
                 "E-puck.receiver_channel"),
    )  # fmt: skip


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
    return Bodiless(_text(node, "name", "robot"), node.name, controller, Pose(x, y, turn),
                    _child_channel(node, "Emitter"), _child_channel(node, "Receiver"))  # fmt: skip
