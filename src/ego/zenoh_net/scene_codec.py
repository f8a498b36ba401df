"""A simulated world's scene (ego.core.scene.Scene) asked over the network: the sans-I/O
request/reply codec of ``ego/NAME/scene`` (docs/zenoh.md).

A request is one JSON object ``{"op": OP, "name": SOLID, "args": [...]}``, ``OP`` one of
:data:`OPS` (the Scene protocol's methods); its reply is ``{"ok": VALUE}`` or
``{"error": KIND, "message": TEXT}``, ``KIND`` ``"KeyError"`` for a solid the scene has
not (as the Scene raises it) or ``"ProtocolError"`` for a malformed request.
:func:`answer` runs a request against a Scene; :func:`request` and :func:`result` are
the asking side's halves. Nothing here touches a network.
"""

from __future__ import annotations

import json
import math
from typing import Any

from ego.core.scene import Scene
from ego.errors import ProtocolError

__all__ = ["MAX_REQUEST_BYTES", "OPS", "answer", "request", "result"]

#: The Scene's methods asked over the network, and how many numbers each takes.
OPS = {"robot_name": 0, "names": 0, "kind": 0, "vertical": 0, "pose": 0, "set_pose": 4,
       "velocity": 0, "reset": 0}  # fmt: skip
#: A request's size, at most (a name and three numbers fit in a few hundred bytes).
MAX_REQUEST_BYTES = 4096


def request(op: str, name: str = "", *args: float) -> bytes:
    """The bytes asking ``op`` of the solid ``name``."""
    return json.dumps({"op": op, "name": name, "args": list(args)}).encode()


def _parse(data: bytes) -> tuple[str, str, list[float]]:
    if len(data) > MAX_REQUEST_BYTES:
        raise ProtocolError(f"scene request of {len(data)} bytes (at most {MAX_REQUEST_BYTES})")
    try:
        asked = json.loads(data)
    except (ValueError, RecursionError) as exc:
        raise ProtocolError(f"scene request is not JSON: {exc}") from exc
    op = asked.get("op") if isinstance(asked, dict) else None
    if op not in OPS:
        raise ProtocolError(f"scene request {data[:60]!r}: op is one of {', '.join(OPS)}")
    name, args = asked.get("name", ""), asked.get("args", [])
    if not isinstance(name, str) or len(name) > 256:
        raise ProtocolError(f"scene request {op}: name {str(name)[:60]!r} is not a string")
    numbers = isinstance(args, list) and all(
        isinstance(a, int | float) and not isinstance(a, bool) and math.isfinite(a) for a in args
    )
    if not numbers or len(args) != OPS[op]:
        raise ProtocolError(f"scene request {op}: takes {OPS[op]} finite numbers, not {args!r}")
    return op, name, [float(a) for a in args]


def _call(scene: Scene, op: str, name: str, args: list[float]) -> Any:
    if op == "robot_name":
        return scene.robot_name
    if op == "names":
        return list(scene.names())
    if op == "kind":
        return scene.kind(name)
    if op == "pose":
        return list(scene.pose(name))
    if op == "vertical":
        return list(scene.vertical)
    if op == "set_pose":  # x, y, z in the world file's frame, then the turn
        scene.set_pose(name, (args[0], args[1], args[2]), args[3])
        return None
    if op == "velocity":
        return list(scene.velocity(name))
    scene.reset()
    return None


def answer(scene: Scene, data: bytes) -> bytes:
    """The reply to the request ``data``, run against ``scene``."""
    try:
        reply: dict[str, Any] = {"ok": _call(scene, *_parse(data))}
    except ProtocolError as exc:
        reply = {"error": "ProtocolError", "message": str(exc)}
    except KeyError as exc:
        reply = {"error": "KeyError", "message": str(exc.args[0]) if exc.args else ""}
    return json.dumps(reply).encode()


def result(data: bytes, where: str) -> Any:
    """What a reply carries; KeyError or ProtocolError as the scene raised it."""
    try:
        reply = json.loads(data)
    except (ValueError, RecursionError) as exc:
        raise ProtocolError(f"{where}: the scene's reply is not JSON: {exc}") from exc
    if not isinstance(reply, dict):
        raise ProtocolError(f"{where}: the scene's reply {data[:60]!r} is not an object")
    if "ok" in reply:
        return reply["ok"]
    message = f"{where}: {reply.get('message', '')}"
    if reply.get("error") == "KeyError":
        raise KeyError(message)
    raise ProtocolError(message)
