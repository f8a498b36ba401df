"""The addresses of a robot ego serve serves: ``tcp://``, ``udp://`` and ``unix://`` URLs."""

from __future__ import annotations

import re

__all__ = [
    "DEFAULT_PORT",
    "parse_url",
]

#: The TCP/UDP port ``ego serve`` listens on unless told otherwise.
DEFAULT_PORT = 4242
_URL = re.compile(r"^(tcp|udp)://(\[[0-9a-fA-F:.]+\]|[^:/\[\]]+)(?::(\d{1,5}))?/?$")


def parse_url(url: str, default_port: int = DEFAULT_PORT) -> tuple[str, str, int]:
    """``tcp://host:port``, ``udp://host:port`` or ``unix:///path`` as (scheme, host or
    path, port); ValueError else."""
    if url.startswith("unix://"):
        path = url.removeprefix("unix://")
        if not path.startswith("/") or len(path.encode()) > 107:
            raise ValueError(f"{url!r} is not unix:///ABSOLUTE/PATH (at most 107 bytes)")
        return "unix", path, 0
    match = _URL.match(url)
    if match is None:
        raise ValueError(f"{url!r} is not tcp://HOST:PORT, udp://HOST:PORT or unix:///PATH")
    scheme, host, port_text = match.groups()
    port = int(port_text) if port_text else default_port
    if port > 65535:
        raise ValueError(f"port {port} in {url!r} is outside 0..65535")
    return scheme, host.strip("[]"), port
