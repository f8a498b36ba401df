"""Webots' scene-tree ``Node``: a supervisor's (ego.controller.supervisor serves the
emulated world's); its type constants (``Node.DISTANCE_SENSOR``) are there for
``getNodeType()``."""

from __future__ import annotations

from typing import NoReturn

from ego.controller.node_types import NODE_TYPES
from ego.errors import UnsupportedDeviceError

__all__ = ["Node", "no_simulation"]


def no_simulation(what: str) -> NoReturn:
    """Refuse a call that supervises a simulation, where there is none."""
    raise UnsupportedDeviceError(
        f"{what} supervises a simulation, and a real e-puck has none to supervise "
        "(on the emulator, --port sim, and in ego swarm, it works)"
    )


class Node:
    """Webots' scene-tree Node: a supervisor's, and there is no scene tree on a robot.
    Its type constants (``Node.DISTANCE_SENSOR``) are there, for ``getNodeType()``."""

    def __init__(self, *args: object, **kwargs: object) -> None:
        no_simulation("Node")


for _number, _name in enumerate(NODE_TYPES):
    setattr(Node, _name, _number)
