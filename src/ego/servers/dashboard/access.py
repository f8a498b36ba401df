"""Who may open the dashboard: the Host it is asked for, the page's Origin, and a token.

Every dashboard has a token, even on loopback, where any program of any user (and any
web page, through DNS rebinding) could otherwise reach it. Off loopback it is an HMAC of
``ego serve``'s shared secret, so a leaked URL opens that dashboard and nothing else, and
changing the secret revokes it; without a secret it is random for the run. The printed
URL carries it once, as notebook servers do: ``GET /?token=T`` logs the browser in with
an HttpOnly, SameSite=Strict cookie and redirects to the bare page, and the page's
WebSocket carries the cookie (a script may put ``?token=T`` on the socket's URL instead).

A request whose Host is not one of the dashboard's names is refused, whatever it
carries: a page of ``evil.test`` whose name the attacker points at 127.0.0.1 reaches the
server with ``Host: evil.test``. The names are loopback's, the address it is bound to
(and, bound to every interface, this machine's names) and any given; an IP literal is
always a name of the server its request reached, so it is never a rebinding. A
WebSocket is also refused when its page came from another origin.
"""

from __future__ import annotations

import hmac
import ipaddress
import secrets
import socket
from collections.abc import Iterable, Mapping
from hashlib import sha256
from urllib.parse import parse_qs, urlsplit

from ego.errors import InsecureSecretError
from ego.net.auth import is_loopback

__all__ = ["Gate", "check_binding", "dashboard_token", "host_name", "is_wildcard", "socket_url",
           "url_host"]  # fmt: skip

_LABEL = b"ego dashboard token v1"
#: Addresses that bind every interface: a URL must name the machine instead.
_WILDCARDS = ("", "0.0.0.0", "::")


def dashboard_token(secret: bytes | None) -> str:
    """The URL token of a dashboard (32 hex digits): derived from its shared secret, or
    random for the run when it has none."""
    if secret is None:
        return secrets.token_hex(16)
    return hmac.new(secret, _LABEL, sha256).hexdigest()[:32]


def check_binding(host: str, secret: bytes | None) -> None:
    """Refuse a dashboard off loopback without a secret (InsecureSecretError)."""
    if secret is None and not is_loopback(host):
        raise InsecureSecretError(
            f"a dashboard on {host} (off loopback) needs a shared secret: "
            "--secret-file FILE (make one with 'ego secret'), or listen on 127.0.0.1"
        )


def is_wildcard(host: str) -> bool:
    """Whether ``host`` binds every interface (0.0.0.0, ::)."""
    return host in _WILDCARDS


def url_host(host: str) -> str:
    """The host a person opens for a dashboard bound to ``host``: this machine's name for
    a wildcard bind (never 0.0.0.0), IPv6 literals in brackets."""
    name = socket.gethostname() if is_wildcard(host) else host
    return f"[{name}]" if ":" in name else name


def socket_url(url: str) -> str:
    """The WebSocket URL of the dashboard whose printed URL is ``url``, with its token
    (for a script: a browser logs in with the URL and its socket carries the cookie)."""
    parts = urlsplit(url)
    token = parse_qs(parts.query).get("token", [""])[0]
    scheme = "wss" if parts.scheme == "https" else "ws"
    return f"{scheme}://{parts.netloc}/ws" + (f"?token={token}" if token else "")


def host_name(header: str | None) -> str | None:
    """The name in a Host header, lower case, without port or brackets (None: no name)."""
    if not header:
        return None
    netloc = header.strip().lower()
    if netloc.startswith("["):
        name, _, _ = netloc[1:].partition("]")
    else:
        name = netloc.rsplit(":", 1)[0] if netloc.count(":") == 1 else netloc
    return name.rstrip(".") or None


def _is_ip(name: str) -> bool:
    try:
        ipaddress.ip_address(name)
    except ValueError:
        return False
    return True


class Gate:
    """The checks of one dashboard (sans-I/O): its names, its token, its cookie."""

    def __init__(self, bind_host: str, secret: bytes | None, names: Iterable[str] = ()) -> None:
        check_binding(bind_host, secret)
        self.token = dashboard_token(secret)
        #: Cookies ignore ports: one name a dashboard, so two on one machine coexist.
        self.cookie_name = "ego-dashboard-" + sha256(self.token.encode()).hexdigest()[:12]
        allowed = {"localhost", bind_host.lower(), *(n.lower().rstrip(".") for n in names)}
        if is_wildcard(bind_host):
            allowed |= {socket.gethostname().lower(), socket.getfqdn().lower()}
        self.names = frozenset(n for n in allowed if n)

    def host_ok(self, header: str | None) -> bool:
        """Whether a request's Host header names this dashboard."""
        name = host_name(header)
        if name is None:
            return False
        return _is_ip(name) or name in self.names or name.endswith(".localhost")

    def origin_ok(self, origin: str | None, host: str | None) -> bool:
        """Whether a WebSocket's Origin is the dashboard's own page (no Origin: not a
        browser page, e.g. a script of the user's, which its token admits)."""
        if origin is None:
            return True
        if host is None or not self.host_ok(host):
            return False
        return urlsplit(origin).netloc.lower() == host.strip().lower()

    def token_ok(self, given: str | None) -> bool:
        """Whether ``given`` is the token (compared in constant time)."""
        return given is not None and hmac.compare_digest(given.encode(), self.token.encode())

    def cookie_ok(self, cookies: Mapping[str, str]) -> bool:
        """Whether a request carries the cookie that logging in with the token set."""
        return self.token_ok(cookies.get(self.cookie_name))

    def admits(self, cookies: Mapping[str, str], query_token: str | None) -> bool:
        """Whether a request may see live data and act: the cookie, or the token."""
        return self.cookie_ok(cookies) or self.token_ok(query_token)
