"""The Zenoh session of ``ego ros2`` and ``ego swarm --ros2``: a client of the ROS machine's
router, and the rule that a router off loopback must be reached with credentials.

ego is a Zenoh **client** of rmw_zenohd (``mode: "client"``, the routers as its only
endpoints, no listener): everything goes through the router. As a peer (rmw_zenoh's own
mode) ego would take part in the peers' direct links, which the router's gossip sets up:
with Zenoh's user-password authentication each side of such a link must hold the
dictionary of the other's credentials, and across two machines each side's loopback
listener cannot be reached at all; Zenoh then routes nothing and says nothing (the
failure of issue 32, item 2). A client needs neither, and nothing can connect to it.

Who is authenticated is the router's to check (its ``dictionary_file``); ego can only
check its own side. A router off loopback is taken as authenticated when the
configuration given to ego (``--zenoh-config``, else EGO_ZENOH_CONFIG) gives ego
credentials to present: ``transport.auth.usrpwd`` with a user and a password, or mutual
TLS (``tls/`` or ``quic/`` endpoints and a client certificate,
``transport.link.tls.connect_certificate``). Without them ego refuses, in one line,
unless told ``allow_unauthenticated`` (``--allow-unauthenticated-router``): anyone who
reaches such a router can publish ``cmd_vel`` and drive the robot. docs/ros2.md gives
the whole recipe.
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

from ego.errors import InsecureSecretError, LinkError
from ego.net.auth import is_loopback
from ego.zenoh_net.sessions import endpoint_host

if TYPE_CHECKING:
    import zenoh

__all__ = ["credentials", "open_router_session", "router_config"]

#: The flag that accepts a router off loopback without credentials.
ALLOW_FLAG = "--allow-unauthenticated-router"


def credentials(config: zenoh.Config, endpoints: Sequence[str]) -> str | None:
    """What ego would present to the routers ``endpoints`` with ``config`` (a phrase for
    messages), or None: no user and password, no TLS client certificate."""
    transport = json.loads(config.get_json("transport")) or {}
    usrpwd = (transport.get("auth") or {}).get("usrpwd") or {}
    if usrpwd.get("user") and usrpwd.get("password"):
        return f"Zenoh user {usrpwd['user']!r}"
    tls = (transport.get("link") or {}).get("tls") or {}
    certificate = tls.get("connect_certificate") or tls.get("connect_certificate_base64")
    if certificate and all(e.startswith(("tls/", "quic/")) for e in endpoints):
        return "a TLS client certificate"
    return None


def router_config(routers: Sequence[str], config_file: str | None = None, *,
                  allow_unauthenticated: bool = False) -> zenoh.Config:  # fmt: skip
    """A client configuration for ``routers`` (the file's, with its credentials), checked:
    InsecureSecretError for a router off loopback with no credentials, unless allowed."""
    import zenoh

    if not routers:
        raise ValueError("ego ros2 needs a router endpoint (the ROS machine's rmw_zenohd)")
    remote = [e for e in routers if not is_loopback(endpoint_host(e))]
    config = zenoh.Config.from_file(config_file) if config_file else zenoh.Config()
    settings: dict[str, Any] = {
        "mode": "client",
        "connect/endpoints": list(routers),
        "listen/endpoints": [],
        "scouting/multicast/enabled": False,
    }
    for key, value in settings.items():
        config.insert_json5(key, json.dumps(value))
    if remote and not allow_unauthenticated and credentials(config, remote) is None:
        where = "the configuration (--zenoh-config or EGO_ZENOH_CONFIG)"
        raise InsecureSecretError(
            f"router {', '.join(remote)} is off loopback and {where} gives ego no Zenoh "
            "credentials (transport.auth.usrpwd user and password, or a TLS client "
            "certificate): anyone who reaches that router can drive the robot. Set up "
            f"Zenoh's authentication (docs/ros2.md) or pass {ALLOW_FLAG}"
        )
    return config


def open_router_session(routers: Sequence[str], config_file: str | None = None, *,
                        allow_unauthenticated: bool = False) -> Any:  # fmt: skip
    """A Zenoh client session of ``routers`` (see the module and :func:`router_config`);
    LinkError if none of them answers (a client needs its router from the start)."""
    import zenoh

    config = router_config(routers, config_file, allow_unauthenticated=allow_unauthenticated)
    try:
        return zenoh.open(config)
    except zenoh.ZError as exc:
        where = ", ".join(routers)
        raise LinkError(f"no router answers at {where}: is rmw_zenohd running there, and "
                        f"does it accept ego's credentials? ({exc})") from exc  # fmt: skip
