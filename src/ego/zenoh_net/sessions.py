"""Opening a Zenoh session for ego: peer mode, where to listen and connect, and the rule
that a session reaching off this machine must use Zenoh's own authentication.

Endpoints are Zenoh locators (``tcp/127.0.0.1:7447``, ``tls/robot.lan:7447``). A
session whose endpoints are all on loopback needs nothing more; one that listens or
connects elsewhere must be given a Zenoh configuration file (``--zenoh-config``) that
sets user-password authentication (``transport.auth.usrpwd``) or uses TLS endpoints
with client authentication: ego refuses to open it otherwise, as ``ego serve`` refuses
to listen off loopback without a secret. Multicast scouting is off: peers find each
other through the endpoints given (and Zenoh's gossip between them), which keeps every
test's traffic on loopback.
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

from ego.errors import InsecureSecretError
from ego.net.auth import is_loopback

if TYPE_CHECKING:
    import zenoh

    from ego.core.environment import Environment

__all__ = ["ZenohSettings", "endpoint_host", "open_session"]

#: Where ``ego serve --zenoh`` listens and controllers connect by default.
DEFAULT_ENDPOINT = "tcp/127.0.0.1:7447"


def endpoint_host(endpoint: str) -> str:
    """The host of a Zenoh locator ``proto/host:port`` (``[v6]`` brackets removed)."""
    _, sep, address = endpoint.partition("/")
    if not sep or not address:
        raise ValueError(f"Zenoh endpoint {endpoint!r} is not PROTO/HOST:PORT")
    host = address.rsplit(":", 1)[0] if ":" in address else address
    return host.strip("[]")


class ZenohSettings:
    """Where a session listens and connects, and the Zenoh configuration file, if any.

    Nothing by default; :meth:`from_environment` fills in what is not given from
    ``EGO_ZENOH_CONNECT`` and ``EGO_ZENOH_LISTEN`` (comma-separated endpoints) and
    ``EGO_ZENOH_CONFIG`` (a Zenoh JSON5 file), as :mod:`ego.core.environment` read them.
    """

    def __init__(
        self,
        listen: Sequence[str] | None = None,
        connect: Sequence[str] | None = None,
        config_file: str | None = None,
    ) -> None:
        self.listen = list(listen or ())
        self.connect = list(connect or ())
        self.config_file = config_file or None

    @classmethod
    def from_environment(
        cls,
        environment: Environment,
        listen: Sequence[str] | None = None,
        connect: Sequence[str] | None = None,
        config_file: str | None = None,
    ) -> ZenohSettings:
        """The settings given, the environment's where one is None."""
        return cls(
            listen if listen is not None else environment.zenoh_listen,
            connect if connect is not None else environment.zenoh_connect,
            config_file or environment.zenoh_config,
        )

    def check(self, config: zenoh.Config) -> None:
        """Refuse endpoints off loopback unless the configuration authenticates peers."""
        remote = [e for e in self.listen + self.connect if not is_loopback(endpoint_host(e))]
        if not remote:
            return
        settings = json.loads(config.get_json("transport"))
        auth = (settings or {}).get("auth") or {}
        usrpwd = auth.get("usrpwd") or {}
        tls = all(e.startswith(("tls/", "quic/")) for e in remote)
        if not (usrpwd.get("user") or usrpwd.get("dictionary_file") or tls):
            raise InsecureSecretError(
                f"Zenoh endpoints off loopback ({', '.join(remote)}) need Zenoh's own "
                "authentication: a --zenoh-config file with transport.auth.usrpwd, or "
                "tls/ endpoints"
            )


def open_session(settings: ZenohSettings) -> zenoh.Session:
    """A peer session with ``settings``' endpoints (checked first, see the module)."""
    import zenoh

    config = (
        zenoh.Config.from_file(settings.config_file) if settings.config_file else zenoh.Config()
    )
    _set(config, "mode", "peer")
    _set(config, "scouting/multicast/enabled", False)
    # Zenoh's peers listen on every interface by default: ego's, on loopback unless told.
    _set(config, "listen/endpoints", settings.listen or ["tcp/127.0.0.1:0"])
    if settings.connect:
        _set(config, "connect/endpoints", settings.connect)
    settings.check(config)
    return zenoh.open(config)


def _set(config: zenoh.Config, key: str, value: Any) -> None:
    config.insert_json5(key, json.dumps(value))
