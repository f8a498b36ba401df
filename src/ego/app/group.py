"""A swarm's robots found on Zenoh and stepped together: the app picks the zenoh backend
and its sessions, the core's :class:`~ego.core.group.RobotGroup` steps them."""

from __future__ import annotations

from typing import Any

from ego.core.environment import read_environment
from ego.core.group import RobotGroup
from ego.core.robot import Robot
from ego.errors import PortNotFoundError

__all__ = ["open_group"]


def open_group(pattern: str, **options: Any) -> tuple[list[Robot], RobotGroup[Robot]]:
    """The robots a Zenoh key expression names (``zenoh://lab/*``: every node under
    ``lab``, found by their liveliness), opened, and a group stepping them in lockstep.
    Close the robots yourself (``for robot in robots: robot.close()``) and the group.

    ``options`` go to each Robot (``zenoh_connect``, ``zenoh_config``).
    """
    # Imported here: zenoh loads only for a group.
    from ego.backends.zenoh_remote import SCHEME, node_names
    from ego.zenoh_net.sessions import DEFAULT_ENDPOINT, ZenohSettings, open_session

    if not pattern.startswith(f"{SCHEME}://"):
        raise ValueError(f"a group pattern is zenoh://KEY_EXPRESSION, not {pattern!r}")
    settings = ZenohSettings.from_environment(
        read_environment(), connect=options.get("zenoh_connect"),
        config_file=options.get("zenoh_config"),
    )  # fmt: skip
    settings.connect = settings.connect or [DEFAULT_ENDPOINT]
    session: Any = open_session(settings)  # zenoh.Session: its close() is untyped
    try:
        names = node_names(session, pattern.removeprefix(f"{SCHEME}://"))
    finally:
        session.close()
    if not names:
        raise PortNotFoundError(f"no robot node matches {pattern}")
    robots: list[Robot] = []
    try:
        for name in names:
            robots.append(Robot(f"{SCHEME}://{name}", **options))
    except BaseException:
        for robot in robots:
            robot.close()
        raise
    return robots, RobotGroup(robots)
