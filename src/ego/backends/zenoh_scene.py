"""The world of an emulated robot node, for its controller's Supervisor: ego's Scene
(ego.core.scene) asked of the node over ``ego/NAME/scene`` (ego.zenoh_net.scene_codec).

A swarm's node (``ego swarm``) serves one: the robots of the swarm by their DEF names,
the world's boxes and markers. Each call is one query; a node that does not answer
within :data:`SCENE_TIMEOUT_S` raises LinkLostError.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from ego.errors import LinkLostError
from ego.zenoh_net.keys import robot_key
from ego.zenoh_net.scene_codec import request, result

if TYPE_CHECKING:
    import zenoh

__all__ = ["SCENE_TIMEOUT_S", "RemoteScene"]

#: How long one request of the scene may take.
SCENE_TIMEOUT_S = 2.0


class RemoteScene:
    """The scene the robot node ``robot`` serves (ego.core.scene.Scene)."""

    def __init__(self, session: zenoh.Session, robot: str) -> None:
        self.session = session
        self.key = robot_key(robot, "scene")
        self._where = f"zenoh://{robot} scene"

    def _ask(self, op: str, name: str = "", *args: float) -> Any:
        for reply in self.session.get(self.key, payload=request(op, name, *args),
                                      timeout=SCENE_TIMEOUT_S):  # fmt: skip
            if reply.ok is not None:
                return result(reply.ok.payload.to_bytes(), self._where)
        raise LinkLostError(f"{self._where}: no answer to {op} within {SCENE_TIMEOUT_S} s")

    @property
    def robot_name(self) -> str | None:
        name = self._ask("robot_name")
        return None if name is None else str(name)

    def names(self) -> tuple[str, ...]:
        return tuple(str(n) for n in self._ask("names"))

    def kind(self, name: str) -> str:
        return str(self._ask("kind", name))

    def pose(self, name: str) -> tuple[float, float, float, float]:
        x, y, z, yaw = (float(v) for v in self._ask("pose", name))
        return x, y, z, yaw

    @property
    def vertical(self) -> tuple[float, float, float]:
        x, y, z = (float(v) for v in self._ask("vertical"))
        return x, y, z

    def set_pose(self, name: str, position: tuple[float, float, float], angle_rad: float) -> None:
        self._ask("set_pose", name, *position, angle_rad)

    def velocity(self, name: str) -> tuple[float, float, float, float, float, float]:
        vx, vy, vz, wx, wy, wz = (float(v) for v in self._ask("velocity", name))
        return vx, vy, vz, wx, wy, wz

    def reset(self) -> None:
        self._ask("reset")
